// Random linear-assembly loops for the property test and the benchmark.
#include "sched/random_loop.hpp"

#include "isa/ops.hpp"

#include <fmt/format.h>

#include <random>
#include <vector>

namespace nesshi::sched {

namespace {

// The operations a body draws from: compute rows whose operands are registers or immediates.
std::vector<int> compute_pool() {
    std::vector<int> pool;
    for (int i = 0; i < isa::kNumOps; ++i) {
        const isa::OpInfo& o = isa::kOps[static_cast<std::size_t>(i)];
        if (o.kind != isa::Kind::Compute || o.num_operands == 0 || !o.operands[0].is_dest) continue;
        bool regs_only = true;
        for (int k = 0; k < o.num_operands; ++k) {
            const auto kind = o.operands[static_cast<std::size_t>(k)].kind;
            regs_only &= kind == isa::OperandKind::IntReg || kind == isa::OperandKind::FloatReg || kind == isa::OperandKind::Imm;
        }
        if (regs_only) pool.push_back(i);
    }
    return pool;
}

// One iteration's values as it is drawn: loads first, then operations over earlier values.
struct Body {
    std::mt19937_64 rng;
    std::vector<int> pool = compute_pool();
    std::vector<std::string> fvals = {"f0", "f1"}, ivals = {"r2", "r3"};
    int nv = 0;

    explicit Body(std::uint64_t seed) : rng(seed) {}
    std::string fresh(std::vector<std::string>& vals) {
        vals.push_back(fmt::format("%v{}", nv++));
        return vals.back();
    }
    std::string pick(const std::vector<std::string>& v) {
        return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
    }
    std::string loads() {
        std::string s = fmt::format("        flw {}, xs(r1)\n", fresh(fvals));
        s += fmt::format("        flw {}, ys(r1)\n", fresh(fvals));
        return s + fmt::format("        lw {}, ys(r1)\n", fresh(ivals));
    }
    std::string compute() {
        const isa::OpInfo& o = isa::kOps[static_cast<std::size_t>(pool[std::uniform_int_distribution<std::size_t>(0, pool.size() - 1)(rng)])];
        std::vector<std::string> srcs;
        for (int j = 1; j < o.num_operands; ++j) {
            const auto kind = o.operands[static_cast<std::size_t>(j)].kind;
            srcs.push_back(kind == isa::OperandKind::FloatReg ? pick(fvals)
                           : kind == isa::OperandKind::IntReg ? pick(ivals)
                                                              : std::to_string(std::uniform_int_distribution<int>(0, 7)(rng)));
        }
        const std::string dst = fresh(o.operands[0].kind == isa::OperandKind::FloatReg ? fvals : ivals);
        std::string line = fmt::format("        {} {}", o.mnemonic, dst);
        for (const auto& s : srcs) line += ", " + s;
        return line + "\n";
    }
};

std::string program(const isa::Machine& m, const std::string& head, const std::string& body) {
    return fmt::format(R"(        .data {}
xs:     .space 1024
ys:     .space 1024
zs:     .space 1024
ws:     .space 1024
        .text
        li r1, 0
        li r2, 3
        li r3, -5
        li r9, 40
        fli f0, 1.5
        fli f1, -0.25
        fli f5, 0.0
{}{}        .endpipeline
        halt
)",
                       fmt::format("0x{:x}", m.memories.front().base + 0x100), head, body);
}

} // namespace

std::string random_linear_loop(std::uint64_t seed, const isa::Machine& m, int compute_ops) {
    Body b(seed);
    std::string body = b.loads();
    for (int k = 0; k < compute_ops; ++k) body += b.compute();
    body += fmt::format("        fadd f5, f5, {}\n", b.fvals.back());
    body += fmt::format("        fsw {}, zs(r1)\n", b.pick(b.fvals));
    body += fmt::format("        sw {}, ws(r1)\n", b.pick(b.ivals));
    body += "        addi r1, r1, 4\n";
    return program(m, "        .pipeline r9\n", body);
}

std::string random_while_loop(std::uint64_t seed, const isa::Machine& m, int compute_ops) {
    Body b(seed);
    auto coin = [&] { return std::uniform_int_distribution<int>(0, 1)(b.rng) == 1; };
    const bool speculate = coin(), step_first = coin(), test_nez = coin();
    static const char* kThresholds[] = {"5.0", "6.0", "7.0", "7.5"};
    const char* threshold = kThresholds[std::uniform_int_distribution<int>(0, 3)(b.rng)];
    const int before = std::uniform_int_distribution<int>(0, compute_ops)(b.rng);
    std::string head = fmt::format("        fli f6, {}\n        .pipeline while\n", threshold);
    if (speculate) head += "        .speculate r1\n";
    std::string body = b.loads();
    if (step_first) body += "        addi r1, r1, 4\n";
    for (int k = 0; k < before; ++k) body += b.compute();
    // Stores and the accumulator before the exit test: the exit paths must complete them.
    const bool effects_first = coin();
    auto effects = [&] {
        const std::string acc = fmt::format("        fadd f5, f5, {}\n", b.fvals.back());
        const std::string stores =
            fmt::format("        fsw {}, zs(r1)\n        sw {}, ws(r1)\n", b.pick(b.fvals), b.pick(b.ivals));
        return coin() ? acc + stores : stores + acc;
    };
    if (effects_first) body += effects();
    // Leave when x[k] > threshold or after 40 iterations (the arrays hold 256 words).
    if (test_nez) {
        body += "        flt %hit, f6, %v0\n        slti %in, r1, 160\n        xori %out, %in, 1\n";
        body += "        or %stop, %hit, %out\n        bnez %stop, exit\n";
    } else {
        body += "        fle %ok, %v0, f6\n        slti %in, r1, 160\n        and %go, %ok, %in\n        beqz %go, exit\n";
    }
    for (int k = before; k < compute_ops; ++k) body += b.compute();
    if (!effects_first) body += effects();
    if (!step_first) body += "        addi r1, r1, 4\n";
    return program(m, head, body);
}

} // namespace nesshi::sched
