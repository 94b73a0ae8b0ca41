// Fuzz target `iss`: the input bytes choose a machine and a program drawn from the operation
// table (blocks of random operations, loads and stores, FIFO words, branches between blocks),
// which the list scheduler (sched::pack_source) bundles legally. The fast and checked engines
// then run it in lock-step under a cycle limit, and the fast engine once more on its own.
// Broken: a crash, a divergence, a dynamic rule broken by scheduled code, or a fast run that
// ends elsewhere than the lock-step one.
#include "bytes.hpp"
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "isa/ops.hpp"
#include "iss/channel.hpp"
#include "iss/fault.hpp"
#include "iss/lockstep.hpp"
#include "iss/processor.hpp"
#include "sched/block.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

using namespace nesshi;
using fuzz::Bytes;

namespace {

constexpr std::uint64_t kCycleLimit = 500;
constexpr int kBufferBytes = 512;

constexpr std::array<const char*, 10> kFloats = {"0.0", "-0.0", "1.5", "-3.25", "1e30", "-1e-30",
                                                 "1e-40", "3.4e38", "0.1", "7.0"};

struct Generator {
    Bytes& in;
    int blocks;
    bool indirect = false; // a jr: control may enter a block in the middle, so hazards are possible

    // r1 holds the buffer address and is never written; r0..r9 and f0..f9 are the values.
    std::string operand(isa::OperandKind kind, bool dest) {
        using K = isa::OperandKind;
        const std::uint8_t b = in.next();
        switch (kind) {
        case K::IntReg: return dest ? fmt::format("r{}", 2 + b % 8) : fmt::format("r{}", b % 10);
        case K::FloatReg: return fmt::format("f{}", b % 10);
        case K::Imm: return b & 0x80 ? std::to_string(std::int32_t(in.word())) : std::to_string(int(b % 64) - 32);
        case K::FloatImm: return kFloats[b % kFloats.size()];
        case K::Mem: return fmt::format("{}(r1)", (b & 0xe0) == 0xe0 ? int(b & 0x7f) : (b % (kBufferBytes / 4)) * 4);
        case K::Target: return fmt::format("L{}", b % blocks);
        case K::Channel: return std::to_string(b % 2);
        }
        return "0";
    }

    std::string op(const isa::OpInfo& o) {
        if (o.kind == isa::Kind::JumpReg) indirect = true;
        std::string line = fmt::format("        {}", o.mnemonic);
        for (int k = 0; k < o.num_operands; ++k) {
            const isa::Operand& opd = o.operands[std::size_t(k)];
            line += (k ? ", " : " ") + operand(opd.kind, opd.is_dest);
        }
        return line + "\n";
    }
};

bool is_control(isa::Kind k) {
    return k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink || k == isa::Kind::JumpReg ||
           k == isa::Kind::Halt;
}

std::string program(Bytes& in, const isa::Machine& m, bool& indirect) {
    std::vector<const isa::OpInfo*> body, control;
    for (const isa::OpInfo& o : isa::kOps) {
        if (o.kind == isa::Kind::Nop) continue;
        (is_control(o.kind) ? control : body).push_back(&o);
    }
    Generator g{in, 1 + in.next() % 4};
    // The values, one op per bundle before the blocks (not a block: the list scheduler would
    // assemble it with max_latency nops per op), then nops until every one has landed.
    std::string text = fmt::format("        .data 0x{:x}\nbuf:    .space {}\n        .text\n        li r1, buf\n",
                                   m.memories.front().base, kBufferBytes);
    for (int r = 2; r < 10; ++r) text += fmt::format("        li r{}, {}\n", r, std::int32_t(in.word()));
    for (int f = 0; f < 10; ++f) text += fmt::format("        fli f{}, {}\n", f, kFloats[in.next() % kFloats.size()]);
    for (std::uint32_t n = 0; n < m.max_latency(); ++n) text += "        nop\n";
    for (int b = 0; b < g.blocks; ++b) {
        text += fmt::format("L{}:\n#pack begin\n", b);
        const int n = in.next() % 16;
        for (int k = 0; k < n; ++k) text += g.op(*body[in.next() % body.size()]);
        // Every block ends in control, which waits for every result to land: blocks join cleanly.
        const std::uint8_t end = in.next();
        text += end % 3 == 0 ? g.op(*control[in.next() % control.size()])
                             : b + 1 < g.blocks ? fmt::format("        jmp L{}\n", b + 1) : "        halt\n";
        text += "#pack end\n";
    }
    indirect = g.indirect;
    return text;
}

// Both engines' channels: channel 0 holds words from the input then closes, channel 1 collects.
struct Channels {
    iss::QueueChannel in0, out1;
    Channels(const std::vector<std::uint32_t>& words) {
        for (std::uint32_t w : words) in0.feed(w);
        in0.close();
    }
    void attach(iss::Processor& p) {
        p.attach_channel(0, &in0);
        p.attach_channel(1, &out1);
    }
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<isa::Machine>& presets = fuzz::presets();
    static const bool verbose = std::getenv("NESSHI_FUZZ_VERBOSE") != nullptr; // print each program and its end
    Bytes in(data, size);
    const isa::Machine& m = presets[in.next() % presets.size()];
    std::vector<std::uint32_t> words(in.next() % 8);
    for (std::uint32_t& w : words) w = in.word();
    bool indirect = false;
    const std::string linear = program(in, m, indirect);

    std::string packed;
    try {
        packed = sched::pack_source(linear, "fuzz.s", m).text;
    } catch (const base::Error& e) {
        if (verbose) std::fprintf(stderr, "%s---- not scheduled: %s\n", linear.c_str(), e.what());
        return 0; // e.g. an operation this machine has no unit for
    }
    const assembler::AsmResult r = assembler::assemble_string(packed, "fuzz.s", m, {});
    fuzz::check(r.ok, "the list scheduler's bundles assemble", linear + "----\n" + packed + r.diagnostics);
    std::shared_ptr<const iss::Program> prog;
    try {
        prog = iss::load_program(r.object, m);
    } catch (const base::Error& e) {
        fuzz::fail("an assembled program loads", packed + e.what());
    }

    iss::Processor fast(prog, iss::Engine::Fast), checked(prog, iss::Engine::Checked), alone(prog, iss::Engine::Fast);
    Channels cf(words), cc(words), ca(words);
    cf.attach(fast);
    cc.attach(checked);
    ca.attach(alone);
    const iss::LockstepResult ls = iss::run_lockstep(fast, checked, kCycleLimit);
    if (verbose)
        std::fprintf(stderr, "%s---- %s after %llu bundles%s\n", packed.c_str(), iss::status_name(ls.status).data(),
                     static_cast<unsigned long long>(ls.bundles), ls.fault ? (": " + ls.fault->message).c_str() : "");
    if (ls.fault) {
        const iss::FaultKind k = ls.fault->kind;
        fuzz::check(k != iss::FaultKind::Divergence, "the engines agree", packed + iss::format_fault(*prog, *ls.fault));
        if (!indirect)
            fuzz::check(k != iss::FaultKind::InflightRead && k != iss::FaultKind::WritePorts &&
                            k != iss::FaultKind::DupWrite && k != iss::FaultKind::WriteOrder,
                        "scheduled code breaks no dynamic rule", packed + iss::format_fault(*prog, *ls.fault));
    }
    if (ls.status != iss::Status::Halted) return 0;
    const iss::Status s = alone.run(kCycleLimit);
    fuzz::check(s == iss::Status::Halted && alone.pc() == fast.pc() && alone.cycle() == fast.cycle() &&
                    alone.memory().hash() == fast.memory().hash() && cf.out1.size() == ca.out1.size(),
                "a fast run ends where the lock-step run does", packed);
    for (std::uint16_t reg = 0; reg < iss::kNumRegs; ++reg)
        fuzz::check(alone.reg(reg) == fast.reg(reg), "a fast run leaves the registers the lock-step run does",
                    packed + iss::reg_name(reg));
    return 0;
}
