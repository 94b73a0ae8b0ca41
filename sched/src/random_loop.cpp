// Random linear-assembly loops for the property test and the benchmark.
#include "sched/random_loop.hpp"

#include "isa/ops.hpp"

#include <fmt/format.h>

#include <random>
#include <vector>

namespace nesshi::sched {

std::string random_linear_loop(std::uint64_t seed, const isa::Machine& m, int compute_ops) {
    std::mt19937_64 rng(seed);
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
    std::vector<std::string> fvals = {"f0", "f1"}, ivals = {"r2", "r3"};
    std::string body;
    int nv = 0;
    auto fresh = [&](std::vector<std::string>& vals) {
        vals.push_back(fmt::format("%v{}", nv++));
        return vals.back();
    };
    body += fmt::format("        flw {}, xs(r1)\n", fresh(fvals));
    body += fmt::format("        flw {}, ys(r1)\n", fresh(fvals));
    body += fmt::format("        lw {}, ys(r1)\n", fresh(ivals));
    auto pick = [&](const std::vector<std::string>& v) { return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)]; };
    for (int k = 0; k < compute_ops; ++k) {
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
        body += line + "\n";
    }
    body += fmt::format("        fadd f5, f5, {}\n", fvals.back());
    body += fmt::format("        fsw {}, zs(r1)\n", pick(fvals));
    body += fmt::format("        sw {}, ws(r1)\n", pick(ivals));
    body += "        addi r1, r1, 4\n";
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
        .pipeline r9
{}        .endpipeline
        halt
)",
                       fmt::format("0x{:x}", m.memories.front().base + 0x100), body);
}

} // namespace nesshi::sched
