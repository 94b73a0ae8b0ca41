// ISS throughput: simulated bundles/s and ops/s of the fast and checked engines on a synthetic
// mix, against a native C++ loop doing the same arithmetic. All figures come from one run.
//
//   build/bench_iss [--iterations N]
#include "assembler/assembler.hpp"
#include "iss/processor.hpp"
#include "iss/stats.hpp"

#include "isa/machine.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <ctime>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using namespace nesshi;

// CPU time of this thread: the benchmark reports per-core throughput, which a busy shared
// machine would understate with wall time.
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

// Four bundles per iteration on the OS (2 IU + 2 FPU): integer ALU, a load and a store,
// float add/sub/multiply chains and the loop branch; 16 operations per iteration.
std::string mix_source(uint32_t iterations) {
    return fmt::format(R"(
        .data 0x1000
buf:    .word 5, 0
        .text
        {{ li r1, 0 ; li r9, {} ; fli f2, 1.0009765625 ; fli f4, 0.9990234375 }}
        {{ li r10, buf ; li r2, 0 ; fli f3, 1.0 ; fli f1, 0.0 }}
        {{ li r4, 0 ; li r6, 0 ; fli f6, 1.0 ; fli f8, 0.0 }}
loop:   {{ addi r1, r1, 1 ; add r2, r2, r1 ; fadd f1, f1, f2 ; fmul f3, f3, f4 }}
        {{ lw r3, 0(r10) ; xor r4, r4, r2 ; fadd f5, f1, f2 ; fmul f6, f6, f4 }}
        {{ sw r4, 4(r10) ; sub r5, r2, r4 ; fsub f7, f5, f3 ; fadd f8, f8, f6 }}
        {{ bne r1, r9, loop ; add r6, r6, r3 ; fadd f9, f7, f8 ; fmul f10, f9, f2 }}
        halt
)",
                       iterations);
}

struct Native {
    uint32_t r2, r4, r5, r6;
    float f1, f3, f8, f10;
};

// The same arithmetic as the loop above, in the same order, in plain C++ (bundle semantics:
// an operation reads the values from before its bundle).
__attribute__((noinline)) Native native_mix(uint32_t iterations, uint32_t* buf) {
    uint32_t r1 = 0, r2 = 0, r4 = 0, r5 = 0, r6 = 0;
    float f1 = 0.0f, f2 = 1.0009765625f, f3 = 1.0f, f4 = 0.9990234375f, f6 = 1.0f, f8 = 0.0f, f9 = 0.0f, f10 = 0.0f;
    do {
        r2 += r1; // same bundle as r1 += 1: reads the old r1
        r1 += 1;
        f1 += f2;
        f3 *= f4;
        uint32_t r3 = buf[0];
        r4 ^= r2;
        float f5 = f1 + f2;
        f6 *= f4;
        buf[1] = r4;
        r5 = r2 - r4;
        float f7 = f5 - f3;
        f8 += f6;
        r6 += r3;
        f10 = f9 * f2; // same bundle as f9 = f7 + f8: reads the old f9
        f9 = f7 + f8;
    } while (r1 != iterations);
    return {r2, r4, r5, r6, f1, f3, f8, f10};
}

struct Run {
    double seconds = 0;
    iss::Stats stats;
    std::array<uint32_t, 4> check{};
};

Run run_iss(const std::shared_ptr<const iss::Program>& prog, iss::Engine e) {
    iss::Processor p(prog, e);
    double t0 = cpu_seconds();
    iss::Status st = p.run();
    double t1 = cpu_seconds();
    if (st != iss::Status::Halted) {
        fmt::print(stderr, "bench: simulation did not halt: {}", p.fault_report());
        std::exit(1);
    }
    Run r;
    r.seconds = t1 - t0;
    r.stats = iss::compute_stats(p);
    r.check = {p.reg(iss::flat_reg(isa::RegFile::Int, 2)), p.reg(iss::flat_reg(isa::RegFile::Int, 6)),
               p.reg(iss::flat_reg(isa::RegFile::Float, 8)), p.reg(iss::flat_reg(isa::RegFile::Float, 10))};
    return r;
}

} // namespace

int main(int argc, char** argv) {
    uint32_t iterations = 25'000'000;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--iterations") == 0) iterations = uint32_t(std::strtoul(argv[i + 1], nullptr, 10));
    if (iterations == 0) iterations = 1;

    isa::Machine m = isa::load_machine("os");
    auto r = assembler::assemble_string(mix_source(iterations), "mix.s", m, {});
    if (!r.ok) {
        fmt::print(stderr, "{}", r.diagnostics);
        return 1;
    }
    auto prog = iss::load_program(r.object, m);

    uint32_t buf[2] = {5, 0};
    // The native loop is short: take the best of five runs so scheduler noise does not inflate it.
    Native n{};
    double native_s = 1e30;
    for (int rep = 0; rep < 5; ++rep) {
        buf[1] = 0;
        double t0 = cpu_seconds();
        n = native_mix(iterations, buf);
        native_s = std::min(native_s, cpu_seconds() - t0);
    }

    Run fast = run_iss(prog, iss::Engine::Fast);
    Run checked = run_iss(prog, iss::Engine::Checked);
    std::array<uint32_t, 4> want = {n.r2, n.r6, std::bit_cast<uint32_t>(n.f8), std::bit_cast<uint32_t>(n.f10)};
    bool same = fast.check == want && checked.check == want;

    fmt::print("ISS throughput, synthetic mix on os: {} iterations x 4 bundles, 16 ops per iteration\n", iterations);
    fmt::print("results bit-identical to the native twin: {}\n\n", same ? "yes" : "NO");
    fmt::print("{:<8} {:>10} {:>14} {:>14} {:>16}\n", "engine", "cpu s", "Mbundles/s", "Mops/s", "slowdown vs native");
    for (auto [name, run] : {std::pair{"fast", &fast}, std::pair{"checked", &checked}}) {
        double b = double(run->stats.bundles), o = double(run->stats.ops);
        fmt::print("{:<8} {:>10.3f} {:>14.1f} {:>14.1f} {:>15.1f}x\n", name, run->seconds, b / run->seconds / 1e6,
                   o / run->seconds / 1e6, run->seconds / native_s);
    }
    fmt::print("{:<8} {:>10.3f} {:>14} {:>14.1f}\n", "native", native_s, "-",
               16.0 * iterations / native_s / 1e6);
    return same ? 0 : 1;
}
