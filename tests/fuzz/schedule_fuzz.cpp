// Fuzz target `schedule`: the input bytes choose a machine (a preset, or a copy of one with
// latencies 1..6 per op class and a branch penalty 0..2) and `#pack begin ... #pack end` blocks of
// straight-line operations from the operation table (compute, loads and stores, FIFO words), with
// `#pack virtual` ranges and %virtual registers, each block ending in a control operation or not
// (a forward branch, `jmp`, `halt`), sometimes with a control operation before its end.
// sched::pack_source bundles them. Broken: a crash, an exception other than base::Error, a control
// operation before a block's end accepted, bundles that do not assemble, or bundles that end in
// other memory, registers or FIFO words than the blocks written sequentially (each op alone, nops
// until it lands, each virtual register on a register of its own), run by iss::run_differential.
#include "bytes.hpp"
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "isa/ops.hpp"
#include "iss/differential.hpp"
#include "sched/block.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

using namespace nesshi;
using fuzz::Bytes;

namespace {

constexpr std::size_t kMaxInput = 384;
constexpr int kBufferBytes = 256;
constexpr int kVirtualBase = 40;  // `#pack virtual` ranges start here (the blocks name r0-r9, f0-f9)
constexpr int kReferenceBase = 72; // the sequential text's register for the k-th virtual of a block

constexpr std::array<const char*, 8> kFloats = {"0.0", "-0.0", "1.5", "-3.25", "1e30", "1e-40", "0.1", "7.0"};

bool is_control(isa::Kind k) {
    return k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink || k == isa::Kind::JumpReg ||
           k == isa::Kind::Halt;
}

// The straight-line rows: everything but control and nop.
const std::vector<const isa::OpInfo*>& body_ops() {
    static const std::vector<const isa::OpInfo*> v = [] {
        std::vector<const isa::OpInfo*> out;
        for (const isa::OpInfo& o : isa::kOps)
            if (!is_control(o.kind) && o.kind != isa::Kind::Nop) out.push_back(&o);
        return out;
    }();
    return v;
}

struct Generator {
    explicit Generator(Bytes& b) : in(b) {}
    Bytes& in;
    int blocks = 1, block = 0;
    bool virt_int = false, virt_float = false; // a `#pack virtual` range is declared
    std::vector<std::string> vint, vfloat;     // virtual values written so far in this block
    int nv = 0;

    std::string reg(isa::RegFile f, bool dest) {
        const std::uint8_t b = in.next();
        const bool virt = (f == isa::RegFile::Int ? virt_int : virt_float) && (b & 0x80);
        std::vector<std::string>& vals = f == isa::RegFile::Int ? vint : vfloat;
        if (virt) {
            if (dest && !vals.empty() && (b & 0x40) && (b & 0x08)) return vals[b % vals.size()]; // written again
            if (dest || vals.empty() || (b & 0x40 && b & 0x20)) { // a new value, or (rarely) one never written
                const std::string n = fmt::format("%{}{}", f == isa::RegFile::Int ? 'a' : 'x', nv++);
                if (dest || b & 0x10) vals.push_back(n);
                return n;
            }
            return vals[b % vals.size()];
        }
        if (f == isa::RegFile::Int) return dest ? fmt::format("r{}", 2 + b % 8) : fmt::format("r{}", b % 10);
        return fmt::format("f{}", b % 10);
    }

    std::string operand(const isa::OpInfo& o, const isa::Operand& opd) {
        using K = isa::OperandKind;
        const std::uint8_t b = in.next();
        switch (opd.kind) {
        case K::IntReg: return reg(isa::RegFile::Int, opd.is_dest);
        case K::FloatReg: return reg(isa::RegFile::Float, opd.is_dest);
        case K::Imm: return b & 0x80 ? std::to_string(std::int32_t(in.word())) : std::to_string(int(b % 64) - 32);
        case K::FloatImm: return kFloats[b % kFloats.size()];
        case K::Mem: { // aligned, inside the buffer
            const int bytes = o.mem_bytes ? o.mem_bytes : 4;
            return fmt::format("{}(r1)", (b % (kBufferBytes / bytes)) * bytes);
        }
        case K::Target: return fmt::format("L{}", block + 1 + b % (blocks - block)); // forward: every run ends
        case K::Channel: return std::to_string(b % 2);
        }
        return "0";
    }

    std::string op(const isa::OpInfo& o) {
        // Sources before destinations, as the allocator reads them.
        std::vector<std::string> text(o.num_operands);
        for (int pass = 0; pass < 2; ++pass)
            for (int k = 0; k < o.num_operands; ++k)
                if (o.operands[std::size_t(k)].is_dest == (pass == 1)) text[std::size_t(k)] = operand(o, o.operands[std::size_t(k)]);
        std::string line = fmt::format("        {}", o.mnemonic);
        for (int k = 0; k < o.num_operands; ++k) line += (k ? ", " : " ") + text[std::size_t(k)];
        return line + "\n";
    }

    std::string control() {
        static const char* kForms[] = {"jmp", "beqz", "bnez", "beq", "blt", "bgeu", "halt"};
        const std::string form = kForms[in.next() % 7];
        const isa::OpInfo& o = isa::kOps[*isa::find_opcode(form)];
        return op(o);
    }
};

struct Program {
    std::string packed_source; // with #pack lines and virtual registers
    std::string sequential;    // each op alone, nops until it lands; virtuals on registers of their own
    bool misplaced_control = false;
};

// The text with every block written sequentially: what the bundles must mean.
std::string sequential_text(const std::string& text, const isa::Machine& m) {
    std::string out, line;
    bool open = false;
    std::map<std::string, int> vregs;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t nl = text.find('\n', at);
        line = text.substr(at, nl - at);
        at = nl + 1;
        if (line.rfind("#pack virtual", 0) == 0) continue;
        if (line.rfind("#pack begin", 0) == 0) {
            open = true;
            vregs.clear();
            continue;
        }
        if (line.rfind("#pack end", 0) == 0) {
            open = false;
            continue;
        }
        if (!open) {
            out += line + "\n";
            continue;
        }
        for (std::size_t p; (p = line.find('%')) != std::string::npos;) {
            std::size_t e = p + 1;
            while (e < line.size() && std::isalnum(static_cast<unsigned char>(line[e]))) ++e;
            const std::string name = line.substr(p, e - p);
            const int k = vregs.emplace(name, static_cast<int>(vregs.size())).first->second;
            line.replace(p, e - p, fmt::format("{}{}", name[1] == 'a' ? 'r' : 'f', kReferenceBase + k));
        }
        out += line + "\n";
        // Until it lands: the next op sees its result, and every write lands in program order.
        const std::size_t b = line.find_first_not_of(" \t"), e = line.find_first_of(" \t", b);
        const auto opc = isa::find_opcode(line.substr(b, e == std::string::npos ? e : e - b));
        for (std::uint32_t n = 1; opc && n < m.latency_of(isa::kOps[*opc]); ++n) out += "        nop\n";
    }
    return out;
}

Program program(Bytes& in, const isa::Machine& m) {
    Program p;
    Generator g(in);
    g.blocks = 1 + in.next() % 4;
    std::string& t = p.packed_source;
    // A few values to start from (the others 0; loads bring the random data in), set before
    // the blocks one op per bundle, then nops until every one has landed.
    t = fmt::format("        .data 0x{:x}\nbuf:    .space {}\n        .text\n        li r1, buf\n", m.memories.front().base,
                    kBufferBytes);
    for (int r = 2; r < 6; ++r) t += fmt::format("        li r{}, {}\n", r, std::int32_t(in.word()));
    for (int f = 0; f < 4; ++f) t += fmt::format("        fli f{}, {}\n", f, kFloats[in.next() % kFloats.size()]);
    for (std::uint32_t n = 0; n < m.max_latency(); ++n) t += "        nop\n";
    const auto& ops = body_ops();
    for (g.block = 0; g.block < g.blocks; ++g.block) {
        t += fmt::format("L{}:\n", g.block);
        const std::uint8_t v = in.next();
        // A range of 1..16 registers, now and then, for the blocks that follow.
        if (v & 1) {
            t += fmt::format("#pack virtual r{}-r{}\n", kVirtualBase, kVirtualBase + (v >> 4));
            g.virt_int = true;
        }
        if (v & 2) {
            t += fmt::format("#pack virtual f{}-f{}\n", kVirtualBase, kVirtualBase + (v >> 4));
            g.virt_float = true;
        }
        t += "#pack begin\n";
        g.vint.clear();
        g.vfloat.clear();
        const int n = in.next() % 13;
        const std::uint8_t shape = in.next();
        const int misplaced = shape % 16 == 0 && n > 0 ? in.next() % n : -1; // a control op before the end
        for (int k = 0; k < n; ++k) {
            if (k == misplaced) {
                t += g.control();
                p.misplaced_control = true;
            }
            t += g.op(*ops[in.next() % ops.size()]);
        }
        if (shape & 0x10) t += g.control();
        t += "#pack end\n";
    }
    t += fmt::format("L{}:\n        halt\n", g.blocks);
    p.sequential = sequential_text(t, m);
    return p;
}

const std::vector<isa::Machine>& machines() { return fuzz::presets(); }

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool verbose = std::getenv("NESSHI_FUZZ_VERBOSE") != nullptr;
    if (size > kMaxInput) return 0;
    Bytes in(data, size);
    const std::uint8_t mb = in.next();
    isa::Machine random;
    const isa::Machine* m = &fuzz::latency_variant(in, machines()[mb % machines().size()], mb & 0x80, random);
    const Program p = program(in, *m);
    std::string packed;
    try {
        packed = sched::pack_source(p.packed_source, "fuzz.pk", *m).text;
    } catch (const base::Error& e) {
        if (verbose) std::fprintf(stderr, "%s---- not scheduled: %s\n", p.packed_source.c_str(), e.what());
        return 0; // a virtual read before written, too few registers, no unit, a misplaced control op
    }
    fuzz::check(!p.misplaced_control, "a control operation before a block's end is refused", p.packed_source + "----\n" + packed);
    const assembler::AsmResult seq = assembler::assemble_string(p.sequential, "seq.s", *m, {});
    if (!seq.ok) { // the blocks alone assembled: only the reference's own registers can differ
        if (verbose) std::fprintf(stderr, "%s---- reference refused:\n%s", p.sequential.c_str(), seq.diagnostics.c_str());
        return 0;
    }
    const assembler::AsmResult pk = assembler::assemble_string(packed, "fuzz.s", *m, {});
    fuzz::check(pk.ok, "the list scheduler's bundles assemble", p.packed_source + "----\n" + packed + pk.diagnostics);
    iss::DiffOptions d;
    d.max_cycles = 20'000;
    d.fifo_words = 128;
    for (int r = 1; r < 10; ++r) d.registers.push_back(fmt::format("r{}", r));
    for (int f = 0; f < 10; ++f) d.registers.push_back(fmt::format("f{}", f));
    d.seed = 1 + in.next();
    const auto diff = iss::run_differential(seq.object, pk.object, *m, d);
    if (verbose) std::fprintf(stderr, "%s---- %s: %s\n", packed.c_str(), m->name.c_str(), diff ? diff->c_str() : "same");
    if (diff && diff->rfind("the sequential version", 0) == 0) return 0; // e.g. more FIFO words read than fed
    fuzz::check(!diff, "the bundles mean what the blocks written sequentially mean",
                fmt::format("machine {}\n{}----\n{}----\n{}", m->name, p.packed_source, packed, diff.value_or("")));
    return 0;
}
