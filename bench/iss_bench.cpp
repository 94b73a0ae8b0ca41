// ISS throughput: simulated bundles/s and ops/s of the fast and checked engines on a synthetic
// mix, against a native C++ loop doing the same arithmetic; then the fast engine on the built-in
// kernels (3DDDA on an empty grid, sphere intersection), against their native twins. All figures
// come from one run.
//
//   build/bench_iss [--iterations N] [--rays N] [--only mix|mix-fast|kernels|dda-os|dda-seq|spheres-ic|spheres-seq]
#include "args.hpp"

#include "assembler/assembler.hpp"
#include "iss/processor.hpp"
#include "iss/stats.hpp"
#include "kernels/abi.hpp"
#include "kernels/image.hpp"
#include "kernels/messages.hpp"
#include "kernels/shape_record.hpp"
#include "kernels/sources.hpp"
#include "kernels/twins/dda.hpp"
#include "kernels/twins/quadric.hpp"
#include "kbuild/runner.hpp"

#include "isa/machine.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <ctime>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
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

// --- The built-in kernels --------------------------------------------------------------------

struct Ray {
    base::Vec3f o, d;
};

// Rays from random points outside the 40^3 grid over [-10, 10]^3, aimed into it.
std::vector<Ray> grid_rays(int n, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        base::Vec3f o{u(rng) * 30.0f, u(rng) * 30.0f, u(rng) * 30.0f};
        base::Vec3f t{u(rng) * 8.0f, u(rng) * 8.0f, u(rng) * 8.0f};
        rays.push_back({o, base::normalize(t - o)});
    }
    return rays;
}


struct KernelRun {
    std::string name, machine;
    double seconds = 0, native_seconds = 0;
    uint64_t bundles = 0, ops = 0;
    double interp_seconds = 0; // the same drive on the threaded interpreter (no compiled runs)
    bool compiled = false;
};

// The time of the whole drive loop (host feeding and draining included: a few words per ray
// against hundreds of bundles).
// The fastest of 5 timings of `once` run `repeat` times (the native twin): CPU seconds per run.
template <class F> double best_native_seconds(int repeat, F&& once) {
    double best = 1e30;
    for (int rep = 0; rep < 5; ++rep) {
        const double t0 = cpu_seconds();
        for (int k = 0; k < repeat; ++k) once();
        best = std::min(best, (cpu_seconds() - t0) / repeat);
    }
    return best;
}

// Timed twice from the same loaded state: with compiled runs (when the kernel has them), then
// after a reset on the threaded interpreter alone (Processor::set_compiled_runs(false)).
template <class Load, class Drive> void time_kernel(KernelRun& r, kbuild::KernelRunner& run, Load&& load, Drive&& drive) {
    r.compiled = run.proc->compiled_runs();
    for (bool compiled : {true, false}) {
        run.proc->reset();
        run.in.drain_all();
        run.out1.drain_all();
        run.out2.drain_all();
        run.proc->set_compiled_runs(compiled);
        load();
        run.run();
        const iss::Stats s0 = iss::compute_stats(*run.proc);
        double t0 = cpu_seconds();
        drive();
        (compiled ? r.seconds : r.interp_seconds) = cpu_seconds() - t0;
        const iss::Stats s1 = iss::compute_stats(*run.proc);
        r.bundles = s1.bundles - s0.bundles;
        r.ops = s1.ops - s0.ops;
    }
}

KernelRun bench_dda(const kernels::SourceSet& src, const std::string& m, int nrays) {
    KernelRun r{"3DDDA, empty 40^3 grid", m};
    kbuild::KernelRunner run(kbuild::assemble_kernel(src, kernels::kernel_path(m != "seq", false), m));
    const kernels::twins::GridGeom g = kernels::twins::cubic_grid(40, -10.0f, 20.0f);
    const kernels::MemImage image = kernels::os_image(g, std::vector<uint8_t>(40 * 40 * 40, 0));
    std::mt19937 rng(5);
    const std::vector<Ray> rays = grid_rays(nrays, rng);
    time_kernel(r, run, [&] { run.load(image); }, [&] {
        uint32_t i = 0;
        for (const Ray& ray : rays) {
            namespace abi = kernels::abi;
            abi::NewRay nr{abi::Tag{i++ % 4096, abi::Kind::eye, 1}.word(), {ray.o.x, ray.o.y, ray.o.z},
                           {ray.d.x, ray.d.y, ray.d.z}, 0.0f, std::numeric_limits<float>::infinity()};
            run.feed(nr.words());
            run.run();
            run.out1.drain_all();
            run.out2.drain_all();
        }
    });
    // The twin: set-up and every voxel step, repeated so that it runs long enough to time.
    volatile int sink = 0;
    r.native_seconds = best_native_seconds(20, [&] {
        int steps = 0;
        for (const Ray& ray : rays) {
            kernels::twins::DdaState st;
            if (!kernels::twins::dda_setup(g, ray.o, ray.d, 0.0f, std::numeric_limits<float>::infinity(), st)) continue;
            do ++steps;
            while (kernels::twins::dda_step(st));
        }
        sink = sink + steps;
    });
    return r;
}

KernelRun bench_spheres(const kernels::SourceSet& src, const std::string& m, int nrays) {
    KernelRun r{"intersection, 40 spheres", m};
    kbuild::KernelRunner run(kbuild::assemble_kernel(src, kernels::kernel_path(m != "seq", true), m));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> p(-2.0f, 2.0f);
    std::vector<kernels::Shape> shapes(40);
    std::vector<std::vector<uint32_t>> lists(1);
    for (uint32_t i = 0; i < shapes.size(); ++i) {
        kernels::Shape& s = shapes[i];
        s.kind_flags = kernels::kShapeQuadric;
        s.w[0] = p(rng) * 0.2f, s.w[1] = p(rng) * 0.2f, s.w[2] = p(rng) * 0.2f;
        s.w[3] = s.w[4] = s.w[5] = 1.0f;
        s.w[12] = -1.0f;
        lists[0].push_back(i);
    }
    const kernels::IcImage im = kernels::ic_image_lists(lists, shapes);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < nrays; ++i) {
        base::Vec3f o{u(rng) * 20.0f, u(rng) * 20.0f, 20.0f};
        base::Vec3f t{u(rng) * 0.3f, u(rng) * 0.3f, 0.0f};
        rays.push_back({o, base::normalize(t - o)});
    }
    time_kernel(r, run, [&] {
        run.load(im.resident);
        run.load(im.global);
    }, [&] {
        uint32_t i = 0;
        for (const Ray& ray : rays) {
            namespace abi = kernels::abi;
            abi::Visit v;
            v.tag = abi::Tag{i++ % 4096, abi::Kind::eye, 1}.word() | abi::kTagReturn;
            v.voxel = 0;
            v.t_out = 1e30f;
            for (int k = 0; k < 3; ++k) v.o[k] = ray.o[k], v.d[k] = ray.d[k];
            v.tmax = std::numeric_limits<float>::infinity();
            run.feed(v.words());
            run.run();
            run.out1.drain_all();
            run.out2.drain_all();
        }
    });
    volatile float sink = 0;
    r.native_seconds = best_native_seconds(4, [&] {
        float acc = 0;
        for (const Ray& ray : rays) {
            float tbest = std::numeric_limits<float>::infinity();
            for (const kernels::Shape& s : shapes) {
                kernels::twins::QuadricHit h = kernels::twins::intersect_quadric(s.w.data(), false, ray.o, ray.d, 0.0f);
                if (h.hit && h.t < tbest) tbest = h.t;
            }
            acc += tbest < 1e30f ? tbest : 0.0f;
        }
        sink = sink + acc;
    });
    return r;
}

// `only`: empty for every kernel, else one of dda-os, dda-seq, spheres-ic, spheres-seq (e.g. to
// count host instructions of one kernel under callgrind).
void print_kernels(int nrays, const std::string& only) {
    const kernels::SourceSet src = kernels::embedded();
    std::vector<KernelRun> runs;
    for (const char* m : {"os", "seq"})
        if (only.empty() || only == std::string("dda-") + m) runs.push_back(bench_dda(src, m, nrays));
    for (const char* m : {"ic", "seq"})
        if (only.empty() || only == std::string("spheres-") + m) runs.push_back(bench_spheres(src, m, nrays));
    fmt::print("\nISS fast engine on the built-in kernels, {} rays each\n\n", nrays);
    fmt::print("(compiled: with the kernel's compiled runs; interp: the threaded interpreter alone, same rays)\n\n");
    fmt::print("{:<26} {:<4} {:>10} {:>8} {:>12} {:>12} {:>12} {:>10} {:>14} {:>10}\n", "kernel", "on", "bundles",
               "cpu s", "Mbundles/s", "Mops/s", "ops/bundle", "vs twin", "interp Mb/s", "speed-up");
    for (const KernelRun& r : runs)
        fmt::print("{:<26} {:<4} {:>10} {:>8.3f} {:>12.1f} {:>12.1f} {:>12.2f} {:>9.1f}x {:>14.1f} {:>9.2f}x{}\n", r.name,
                   r.machine, r.bundles, r.seconds, double(r.bundles) / r.seconds / 1e6, double(r.ops) / r.seconds / 1e6,
                   double(r.ops) / double(r.bundles), r.seconds / r.native_seconds,
                   double(r.bundles) / r.interp_seconds / 1e6, r.interp_seconds / r.seconds,
                   r.compiled ? "" : "  (not compiled)");
}

} // namespace

int main(int argc, char** argv) {
    const nesshi::bench::Args args = nesshi::bench::parse_args(
        argc, argv,
        "usage: bench_iss [--iterations N] [--rays N] [--only mix|mix-fast|kernels|dda-os|dda-seq|spheres-ic|spheres-seq]",
        {"--iterations", "--rays", "--only"});
    uint32_t iterations = uint32_t(std::max(0L, args.number("--iterations", 25'000'000)));
    const int rays = int(std::max(1L, args.number("--rays", 4000)));
    std::string only = args.text("--only", "");
    // --only mix-fast: the mix on the fast engine alone (to count its host instructions).
    const bool fast_only = only == "mix-fast";
    if (fast_only) only = "mix";
    if (iterations == 0) iterations = 1;
    if (!only.empty() && only != "mix") {
        print_kernels(rays, only == "kernels" ? "" : only);
        return 0;
    }

    isa::Machine m = isa::load_machine("os");
    auto r = assembler::assemble_string(mix_source(iterations), "mix.s", m, {});
    if (!r.ok) {
        fmt::print(stderr, "{}", r.diagnostics);
        return 1;
    }
    auto prog = iss::load_program(r.object, m);

    uint32_t buf[2] = {5, 0};
    // One native call is 30-60 ms, whose time varied 2x between runs: time kNativeRepeat calls
    // back to back (about half a second), best of three, so the ratio is stable.
    constexpr int kNativeRepeat = 12;
    Native n{};
    double native_s = 1e30;
    for (int rep = 0; rep < 3; ++rep) {
        double t0 = cpu_seconds();
        for (int k = 0; k < kNativeRepeat; ++k) {
            buf[1] = 0;
            n = native_mix(iterations, buf);
        }
        native_s = std::min(native_s, (cpu_seconds() - t0) / kNativeRepeat);
    }

    Run fast = run_iss(prog, iss::Engine::Fast);
    Run checked = fast_only ? fast : run_iss(prog, iss::Engine::Checked);
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
    if (only != "mix") print_kernels(rays, "");
    return same ? 0 : 1;
}
