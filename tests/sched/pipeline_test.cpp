// sched/pipeline.hpp: linear assembly in, pipelined code out, checked by simulation. A property
// test draws random loops from the operation table and schedules them for the presets.
#include "sched/pipeline.hpp"

#include "isa/machine.hpp"
#include "isa/ops.hpp"
#include "iss/differential.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <random>
#include <string>
#include <vector>

using namespace nesshi;

namespace {

std::optional<std::string> check(const std::string& text, const isa::Machine& m, sched::PipelineResult* out = nullptr) {
    const sched::PipelineResult r = sched::pipeline_source(text, "t.sa", m, {});
    if (out) *out = r;
    iss::DiffOptions d;
    d.registers = r.source_registers;
    return sched::verify(text, "t.sa", m, {}, sched::verification_trips(r),
                         [&](const isa::ObjectFile& a, const isa::ObjectFile& b) { return iss::run_differential(a, b, m, d); });
}

std::string data_base(const isa::Machine& m) { return fmt::format("0x{:x}", m.memories.front().base + 0x100); }

const char* kSaxpy = R"(# machine: os
        .data 0x1000
xs:     .space 256
ys:     .space 256
        .text
        li r1, 0
        li r9, 64
        fli f0, 2.5
        .pipeline r9
        flw %x, xs(r1)
        flw %y, ys(r1)
        fmul %t, f0, %x
        fadd %s, %t, %y
        fsw %s, ys(r1)
        addi r1, r1, 4
        .endpipeline
        halt
)";

// One random loop body: loads from two input arrays, compute ops drawn from the operation
// table over earlier values and live-in registers, stores of some values, an accumulator.
std::string random_loop(std::mt19937& rng, const isa::Machine& m, int compute_ops) {
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
                       data_base(m), body);
}

} // namespace

TEST_CASE("saxpy pipelines at its bound and equals its sequential meaning", "[unit][sched][pipeline]") {
    sched::PipelineResult r;
    CHECK(check(kSaxpy, isa::load_machine("os"), &r) == std::nullopt);
    CHECK(r.ii == 3); // 2 loads + store + step + loop control on the OS's 2 integer units
    CHECK(r.ii == r.res_mii);
    CHECK(r.stages == 2);
    CHECK(r.pipelined.find("SOFTWARE PIPELINE INFORMATION") != std::string::npos);
    CHECK(check(kSaxpy, isa::load_machine("os-real")) == std::nullopt);
}

TEST_CASE("a recurrence through memory bounds the II", "[unit][sched][pipeline]") {
    // x[i+1] = x[i] * 0.5 + 0.5: load, fmul, fadd, store, and the next iteration's load.
    const std::string text = R"(# machine: os
        .data 0x1000
xs:     .space 1024
        .text
        li r1, 0
        li r9, 100
        fli f0, 0.5
        .pipeline r9
        flw %a, xs(r1)
        fmul %b, %a, f0
        fadd %c, %b, f0
        fsw %c, xs+4(r1)
        addi r1, r1, 4
        .endpipeline
        halt
)";
    sched::PipelineResult r;
    CHECK(check(text, isa::load_machine("os"), &r) == std::nullopt);
    CHECK(r.rec_mii == 4);
    CHECK(r.ii == 4);
}

TEST_CASE("bad linear assembly is a clear error", "[unit][sched][pipeline]") {
    const isa::Machine os = isa::load_machine("os");
    CHECK_THROWS_WITH(sched::pipeline_source("halt\n", "t.sa", os, {}), "t.sa: error: no .pipeline region");
    CHECK_THROWS_WITH(sched::pipeline_source(".pipeline r9\nfadd %a, %b, f1\n.endpipeline\nhalt\n", "t.sa", os, {}),
                      Catch::StartsWith("t.sa:2: error: %b is read before it is written"));
    CHECK_THROWS_WITH(sched::pipeline_source(".pipeline r9\nbnez r1, x\n.endpipeline\n", "t.sa", os, {}),
                      Catch::Contains("no control flow inside a .pipeline region"));
    CHECK_THROWS_WITH(sched::pipeline_source(".pipeline f9\n.endpipeline\n", "t.sa", os, {}),
                      Catch::Contains("integer register holding the trip count"));
    CHECK_THROWS_WITH(sched::pipeline_source(".pipeline r9\nfadd %a, f1, f2\nfadd %a, f1, f2\n.endpipeline\n", "t.sa", os, {}),
                      Catch::Contains("%a is written twice"));
}

TEST_CASE("random loops from the operation table pipeline and verify on every preset", "[unit][sched][pipeline][property]") {
    std::mt19937 rng(12345);
    for (const char* name : {"os", "ic", "os-real", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        for (int k = 0; k < 25; ++k) {
            const std::string text = random_loop(rng, m, 3 + k % 20);
            INFO(name << " loop " << k << ":\n" << text);
            sched::PipelineResult r;
            std::optional<std::string> diff;
            REQUIRE_NOTHROW(diff = check(text, m, &r));
            CHECK(diff == std::nullopt);
            CHECK(r.ii >= r.mii);
        }
    }
}
