// Fuzz target `pipeline`: the input bytes choose a machine (os, ic, os-real, ic-real, or a copy
// of one of them with latencies 1..6 per op class and a branch penalty 0..2) and a linear-assembly
// loop: sched::random_linear_loop / random_while_loop with a seed from the bytes, or a loop written
// from the bytes (loads and stores through the induction register, through virtual and physical
// base registers computed from it, FIFO words, an accumulator, physical temporaries, the induction
// stored as data; counted or `.pipeline while`, with `.speculate` (of r1 and of virtual bases), `.carry`
// and `.liveout`).
// sched::pipeline_source pipelines it; a base::Error (no schedule, registers, malformed) is fine.
// Otherwise the pipelined code runs against the region's sequential meaning (r.linear) with
// iss::run_differential on random data and FIFO words, at one trip count
// 0..23 from the bytes, sometimes with a `.trip` whose minimum it honours (a while loop:
// sched::verify_while on two data sets).
// Broken: a crash, any difference in memory, registers or words sent, the pipelined code faulting
// or not halting where the sequential one halts, or a verification that does not assemble.
#include "bytes.hpp"
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "isa/ops.hpp"
#include "iss/differential.hpp"
#include "sched/pipeline.hpp"
#include "sched/random_loop.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace nesshi;
using fuzz::Bytes;

namespace {

constexpr std::size_t kMaxInput = 256;     // longer inputs add nothing a loop can hold
constexpr std::uint64_t kCycleBudget = 60'000;
constexpr std::size_t kFifoWords = 512;    // per received channel: more than most loops here read
constexpr int kWhileRuns = 2;

const std::vector<isa::Machine>& machines() {
    static const std::vector<isa::Machine> v = [] {
        std::vector<isa::Machine> out;
        for (const char* n : {"os", "ic", "os-real", "ic-real"}) out.push_back(isa::load_machine(n));
        return out;
    }();
    return v;
}

// The compute rows a body draws from: a destination, register or small-immediate sources.
const std::vector<const isa::OpInfo*>& compute_pool() {
    static const std::vector<const isa::OpInfo*> pool = [] {
        std::vector<const isa::OpInfo*> p;
        for (const isa::OpInfo& o : isa::kOps) {
            if (o.kind != isa::Kind::Compute || o.num_operands == 0 || !o.operands[0].is_dest) continue;
            if (o.mnemonic == "li" || o.mnemonic == "fli") continue;
            bool ok = true;
            for (int k = 0; k < o.num_operands; ++k) {
                const auto kind = o.operands[std::size_t(k)].kind;
                ok &= kind == isa::OperandKind::IntReg || kind == isa::OperandKind::FloatReg || kind == isa::OperandKind::Imm;
            }
            if (ok) p.push_back(&o);
        }
        return p;
    }();
    return pool;
}

// Data: a pad, four arrays of 2 KB (r1 and r13 reach 800, a stride-2 base 1600, offsets -16..31), a pad.
std::string frame(const isa::Machine& m, const std::string& head, const std::string& body, const std::string& tail) {
    return fmt::format(R"(        .data 0x{:x}
pad0:   .space 64
xs:     .space 2048
ys:     .space 2048
zs:     .space 2048
ws:     .space 2048
pad1:   .space 64
        .text
        li r1, 0
        li r2, 3
        li r3, -5
        li r4, 7
        li r5, 0
        li r6, 1
        li r9, 40
        li r10, xs
        li r11, ys
        li r12, ws
        li r13, 0
        fli f0, 1.5
        fli f1, -0.25
        fli f5, 0.0
        fli f6, 5.0
        fli f7, 2.0
        fli f8, -1.0
{}{}        .endpipeline
{}        halt
)",
                       m.memories.front().base + 0x100, head, body, tail);
}

// A loop written from the bytes. r1 is the induction (step 4 or 8), r13 a second one or unused;
// r10 / r11 hold xs / ys, r12 a physical base (ws, or r1 + r10/r11 recomputed in the body); f5
// the accumulator; r4-r6, f7-f8 physical temporaries (loop-carried when read before written).
struct LoopGen {
    explicit LoopGen(Bytes& b) : in(b) {}
    Bytes& in;
    bool is_while = false, carry = false;
    std::vector<std::string> fv = {"f0", "f1", "f5", "f7", "f8"}, iv = {"r2", "r3", "r4", "r5", "r6", "r1"};
    std::vector<std::string> vbases; // virtual bases defined so far: (name)
    int nv = 0;
    bool r13_stepped = false;
    std::string body;

    std::string fresh(std::vector<std::string>& pool, char kind = 'v') {
        std::string n = fmt::format("%{}{}", kind, nv++);
        pool.push_back(n);
        return n;
    }
    std::string pick(const std::vector<std::string>& v) { return v[in.next() % v.size()]; }
    void line(const std::string& s) { body += "        " + s + "\n"; }

    // An address for an access of `bytes`: offset aligned to it, on one of the bases.
    std::string addr(int bytes) {
        const std::uint8_t b = in.next(), o = in.next();
        const int off = bytes == 4 ? (o % 12 - 4) * 4 : bytes == 2 ? (o % 24 - 8) * 2 : o % 48 - 16;
        static const char* kArrays[] = {"xs", "ys", "zs", "ws"};
        switch (b % 5) {
        case 0:
        case 1: return fmt::format("{}{:+d}(r1)", kArrays[b / 5 % 4], off);
        case 2:
            if (!vbases.empty()) return fmt::format("{}({})", off, vbases[b / 5 % vbases.size()]);
            [[fallthrough]];
        case 3: return fmt::format("{}(r12)", off);
        default: return fmt::format("{}{:+d}(r13)", kArrays[b / 5 % 4], off);
        }
    }

    void op() {
        const std::uint8_t k = in.next();
        switch (k % 12) {
        case 0: line(fmt::format("flw {}, {}", fresh(fv), addr(4))); break;
        case 1: {
            static const char* kLoads[] = {"lw", "lh", "lhu", "lb", "lbu"};
            static const int kBytes[] = {4, 2, 2, 1, 1};
            const int w = k / 12 % 5;
            line(fmt::format("{} {}, {}", kLoads[w], fresh(iv), addr(kBytes[w])));
            break;
        }
        case 2: {
            const std::string v = pick(fv);
            line(fmt::format("fsw {}, {}", v, addr(4)));
            break;
        }
        case 3: { // sw r1, ys(r1): an induction stored as data (finding P2)
            static const char* kStores[] = {"sw", "sh", "sb"};
            static const int kBytes[] = {4, 2, 1};
            const int w = k / 12 % 3;
            const std::string v = pick(iv);
            line(fmt::format("{} {}, {}", kStores[w], v, addr(kBytes[w])));
            break;
        }
        case 4:
        case 5:
        case 6: compute(k / 12); break;
        case 7: { // FIFO words: in on channel 0 or 1, out on channel 1 or 2
            const std::uint8_t c = in.next();
            if (c & 1) line(fmt::format("{} {}, {}", c & 2 ? "frecv" : "recv", c & 2 ? fresh(fv) : fresh(iv), c >> 2 & 1));
            else {
                const bool f = c & 2;
                line(fmt::format("{} {}, {}", f ? "fsend" : "send", 1 + (c >> 2 & 1), f ? pick(fv) : pick(iv)));
            }
            break;
        }
        case 8: { // a base computed from the induction (finding P1)
            const std::uint8_t c = in.next();
            const char* arr = c & 1 ? "r11" : "r10";
            switch (c >> 1 & 3) {
            case 0: line(fmt::format("add r12, r1, {}", arr)); break;
            case 1: {
                const std::string s = fresh(iv, 's');
                line(fmt::format("slli {}, r1, 1", s));
                const std::string p = fmt::format("%p{}", nv++);
                line(fmt::format("add {}, {}, {}", p, s, arr));
                vbases.push_back(p);
                break;
            }
            default: {
                const std::string p = fmt::format("%p{}", nv++);
                line(fmt::format("add {}, r1, {}", p, arr));
                vbases.push_back(p);
                break;
            }
            }
            break;
        }
        case 9: line(fmt::format("fadd f5, f5, {}", pick(fv))); break;
        case 10: { // a physical temporary
            const std::uint8_t c = in.next();
            if ((c & 1) && !carry) line(fmt::format("fmul {}, {}, {}", c & 2 ? "f7" : "f8", pick(fv), pick(fv)));
            else line(fmt::format("add {}, {}, {}", (c >> 1) % 3 == 0 ? "r4" : (c >> 1) % 3 == 1 ? "r5" : "r6", pick(iv), pick(iv)));
            break;
        }
        default: // a second induction, stepped once
            if (!r13_stepped) line(fmt::format("addi r13, r13, {}", k / 12 % 2 ? 8 : 4));
            r13_stepped = true;
            break;
        }
    }

    void compute(int salt) {
        const auto& pool = compute_pool();
        const isa::OpInfo& o = *pool[(in.next() + salt) % pool.size()];
        std::vector<std::string> srcs;
        for (int j = 1; j < o.num_operands; ++j) {
            const auto kind = o.operands[std::size_t(j)].kind;
            srcs.push_back(kind == isa::OperandKind::FloatReg ? pick(fv)
                           : kind == isa::OperandKind::IntReg ? pick(iv)
                                                              : std::to_string(int(in.next() % 16) - 4));
        }
        const std::string dst = fresh(o.operands[0].kind == isa::OperandKind::FloatReg ? fv : iv);
        std::string s = fmt::format("{} {}", o.mnemonic, dst);
        for (const auto& x : srcs) s += ", " + x;
        line(s);
    }
};

// The registers a text names (as the tool finds them: never a %virtual, never in a comment).
std::vector<std::string> named_registers(const std::string& text) {
    std::set<std::pair<char, int>> regs;
    bool comment = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') comment = false;
        if (c == '#') comment = true;
        if (comment || (c != 'r' && c != 'f')) continue;
        if (i > 0 && (std::isalnum(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '_' || text[i - 1] == '%')) continue;
        std::size_t e = i + 1;
        while (e < text.size() && std::isdigit(static_cast<unsigned char>(text[e]))) ++e;
        if (e == i + 1 || (e < text.size() && (std::isalnum(static_cast<unsigned char>(text[e])) || text[e] == '_'))) continue;
        regs.insert({c, std::stoi(text.substr(i + 1, e - i - 1))});
    }
    std::vector<std::string> out;
    for (const auto& [f, n] : regs) out.push_back(fmt::format("{}{}", f, n));
    return out;
}

std::string bytes_loop(Bytes& in, const isa::Machine& m) {
    const std::uint8_t shape = in.next();
    LoopGen g(in);
    g.is_while = shape & 1;
    g.carry = g.is_while && (shape & 2);
    if (g.carry) { // %c is read before its write: the value of the iteration before (f7 at first)
        g.fv = {"f0", "f1", "f5", "%c"};
    }
    const int n = 1 + in.next() % 14;
    const int step_at = in.next() % (n + 1), test_at = in.next() % (n + 1), carry_at = in.next() % (n + 1);
    const int step = shape & 4 ? 8 : 4;
    std::string liveout; // `.liveout %v, REG` of a value defined before the exit test
    for (int k = 0; k <= n; ++k) {
        if (k == step_at) g.line(fmt::format("addi r1, r1, {}", step));
        if (g.carry && k == carry_at) g.line(fmt::format("fmul %c, {}, f0", g.pick(g.fv)));
        if (g.is_while && k == test_at) { // leave when a value exceeds 5.0 or r1 reaches 160
            std::vector<std::string> defined;
            for (const auto* pool : {&g.fv, &g.iv})
                for (const std::string& v : *pool)
                    if (v[0] == '%' && v != "%c") defined.push_back((pool == &g.fv ? "f9 " : "r7 ") + v);
            if ((shape & 32) && !defined.empty()) {
                const std::string& c = defined[in.next() % defined.size()];
                liveout = fmt::format("        .liveout {}, {}\n", c.substr(3), c.substr(0, 2));
            }
            g.line(fmt::format("flt %hit, f6, {}", g.pick(g.fv)));
            g.line("slti %in, r1, 160");
            g.line("xori %out, %in, 1");
            g.line("or %stop, %hit, %out");
            g.line("bnez %stop, exit");
        }
        if (k < n) g.op();
    }
    std::string head = g.is_while ? "        .pipeline while\n" : "        .pipeline r9\n";
    if (g.is_while && (shape & 8)) head += "        .speculate r1\n";
    if (g.is_while && (shape & 64)) // bases computed from the induction: every address stays in the data
        for (const std::string& p : g.vbases) head += "        .speculate " + p + "\n";
    if (g.carry) head += shape & 16 ? "        .carry %c, f7, f7, f8\n" : "        .carry %c, f7\n";
    head += liveout;
    return frame(m, head, g.body, "");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool verbose = std::getenv("NESSHI_FUZZ_VERBOSE") != nullptr; // print each loop and its fate
    if (size > kMaxInput) return 0;
    Bytes in(data, size);
    const std::uint8_t mb = in.next();
    isa::Machine random;
    const isa::Machine* m = &fuzz::latency_variant(in, machines()[mb % 4], mb & 4, random);
    const std::uint8_t kind = in.next();
    std::string text;
    switch (kind % 4) {
    case 0: text = sched::random_linear_loop(in.word64(), *m, 1 + kind / 4 % 16); break;
    case 1: text = sched::random_while_loop(in.word64(), *m, 1 + kind / 4 % 16); break;
    default: text = bytes_loop(in, *m); break;
    }
    const std::uint8_t pick = in.next(), first_trip = in.next();

    sched::PipelineOptions opts;
    iss::DiffOptions d;
    d.registers = named_registers(text); // what the tool compares too: never its scratch registers
    d.max_cycles = kCycleBudget;
    d.fifo_words = kFifoWords;
    d.seed = 1 + pick % 4;
    // A difference is the pipeliner's only when the sequential meaning itself runs to its halt.
    bool sequential_fails = false;
    auto differ = [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip, const iss::DiffOptions& o) -> std::optional<std::string> {
        auto diff = iss::run_differential(lin, pip, *m, o);
        if (diff && diff->rfind("the sequential version", 0) == 0) {
            sequential_fails = true;
            return std::nullopt;
        }
        return diff;
    };
    std::optional<std::string> failure;
    std::string what, pipelined;
    // The verification's own errors: its texts do not assemble. Any other base::Error (or the
    // documented std::runtime_error) is a loop the tool refuses: no schedule, registers, malformed.
    auto refused = [&](const std::runtime_error& e) {
        const auto* be = dynamic_cast<const base::Error*>(&e);
        const std::string msg = be ? be->message() : e.what();
        fuzz::check(msg.rfind("the pipelined loop does not assemble cleanly", 0) != 0 &&
                        msg.rfind("the sequential meaning does not assemble cleanly", 0) != 0,
                    "a pipelined loop's verification assembles", text + "----\n" + pipelined + "----\n" + e.what());
        if (verbose) std::fprintf(stderr, "%s---- not pipelined: %s\n", text.c_str(), e.what());
    };
    int ii = 0, stages = 0, unroll = 0;
    if (text.find(".pipeline while") != std::string::npos) {
        // Pipelined once, run on kWhileRuns data sets.
        try {
            const sched::PipelineResult r = sched::pipeline_source(text, "fuzz.sa", *m, opts);
            const sched::WhileVerification v = sched::verify_while(
                r, "fuzz.sa", *m, kWhileRuns,
                [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip, std::uint64_t seed, std::uint32_t& exits) {
                    iss::DiffOptions o = d;
                    o.seed = seed + pick;
                    exits = 0;
                    return differ(lin, pip, o);
                });
            failure = v.failure;
            what = fmt::format("while loop, {} runs, {} exit paths", kWhileRuns, v.path_count);
        } catch (const std::runtime_error& e) {
            refused(e);
            return 0;
        }
    } else {
        // One trip count per input, 0..23 (the sequential path, the shortest pipelined runs and
        // the unroll remainders of these loops all lie there): the fuzzer varies it, so one
        // pipelining and one run per input keep the executions per second up.
        sched::PipelineResult r;
        const std::uint32_t t0 = first_trip % 24;
        // Sometimes a `.trip MIN[, EXPECTED]` that the count run honours: the code drops the paths
        // MIN makes dead and the schedule is chosen by whole-run cycles; it must still be exact.
        if ((pick & 8) && t0 > 0) {
            const std::uint32_t min = 1 + (pick >> 4) % t0;
            const std::size_t at = text.find('\n', text.find(".pipeline r9")) + 1;
            text.insert(at, pick & 4 ? fmt::format("        .trip {}, {}\n", min, min + pick % 4 * 8) : fmt::format("        .trip {}\n", min));
        }
        try {
            r = sched::pipeline_source(text, "fuzz.sa", *m, opts);
            const sched::TripPrograms run = sched::with_trip(r, *m, t0);
            pipelined = run.pipelined;
            ii = r.ii, stages = r.stages, unroll = r.unroll;
            const assembler::AsmResult lin = assembler::assemble_string(run.linear, "fuzz.sa", *m, {});
            const assembler::AsmResult pip = assembler::assemble_string(run.pipelined, "fuzz.sa", *m, {});
            fuzz::check(lin.ok && lin.warnings == 0 && pip.ok && pip.warnings == 0, "a pipelined loop assembles cleanly",
                        text + "----\n" + run.linear + "----\n" + run.pipelined + lin.diagnostics + pip.diagnostics);
            what = fmt::format("trips {}", t0);
            if (auto diff = differ(lin.object, pip.object, d)) failure = fmt::format("trip count {}: {}", t0, *diff);
        } catch (const std::runtime_error& e) {
            refused(e);
            return 0;
        }
    }
    if (verbose)
        std::fprintf(stderr, "%s---- %s, II %d, %d stages, unroll %d, %s: %s%s\n", text.c_str(), m->name.c_str(), ii, stages,
                     unroll, what.c_str(), failure ? failure->c_str() : "same", sequential_fails ? " (a sequential run failed)" : "");
    fuzz::check(!failure, "the pipelined loop equals its sequential meaning",
                fmt::format("machine {} (latencies {}, branch penalty {})\n{}----\n{}----\n{}: {}\n", m->name,
                            fmt::join(m->latency, " "), m->branch_penalty, text, pipelined, what, failure.value_or("")));
    return 0;
}
