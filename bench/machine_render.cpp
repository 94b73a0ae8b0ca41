// Benchmark: the simulated machine's speed. Renders one scene through a model (default: balls,
// model V, grid 50, 512 x 512, one PE on one host thread) and the same prepared scene with the native
// tracer, and prints wall times, simulated bundles per second and their ratio, measured in one run;
// also per CPU second of this process, which a busy shared machine does not inflate, with the
// built-in kernels' compiled runs and again without them (the threaded interpreter).
// --paper DIR also times the whole `nesshi paper` matrix into DIR (must not hold cells yet, else
// the finished ones are loaded, not timed): the target is under 30 minutes on 2 cores.
// Usage: bench_machine_render [--scene S] [--model V|M|S] [--grid N] [--size N] [--paper DIR]
#include "args.hpp"

#include "iss/compiled.hpp"
#include "machine/machine.hpp"
#include "paper/paper.hpp"
#include "rt/render.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <string>

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU time of the whole process (every host thread of the simulation).
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

} // namespace

int main(int argc, char** argv) {
    using namespace nesshi;
    using namespace nesshi::rt;
    const bench::Args args =
        bench::parse_args(argc, argv, "usage: bench_machine_render [--scene S] [--model V|M|S] [--grid N] [--size N] [--paper DIR]",
                          {"--scene", "--model", "--grid", "--size", "--paper"});
    const std::string scene = args.text("--scene", "balls"), model = args.text("--model", "V"),
                      paper_dir = args.text("--paper", "");
    const int grid = int(args.number("--grid", 50)), size = int(args.number("--size", 512));
    try {
        machine::Options mo;
        if (!machine::parse_model(model, mo.model)) throw std::runtime_error("unknown model " + model);
        mo.threads = 1;
        const PreparedScene prep = prepare(load_scene(scene), grid);
        RenderOptions opt;
        opt.width = opt.height = size;

        opt.threads = 1;
        const auto t_native = std::chrono::steady_clock::now();
        const double c_native = cpu_seconds();
        const RenderResult native = render_native(prep, opt);
        const double native_s = seconds_since(t_native), native_cpu = cpu_seconds() - c_native;

        // With the built-in kernels' compiled runs (iss/compiled.hpp), then on the threaded
        // interpreter alone: the two speeds and their ratio, in one run.
        auto machine_run = [&](bool compiled, double& cpu) {
            iss::set_compiled_enabled(compiled);
            const double c0 = cpu_seconds();
            machine::Result r = machine::render(prep, opt, mo);
            cpu = cpu_seconds() - c0;
            return r;
        };
        const bool compiled_default = iss::compiled_enabled();
        double machine_cpu = 0, interp_cpu = 0;
        const machine::Result m = machine_run(compiled_default, machine_cpu);
        const machine::Result mi = machine_run(false, interp_cpu);
        iss::set_compiled_enabled(compiled_default);
        const machine::Stats& s = m.machine;
        fmt::print("{} {}x{} grid {}, model {}, 1 PE, 1 host thread{}\n", scene, size, size, grid, model,
                   compiled_default ? "" : " (NESSHI_COMPILED=0: both runs interpreted)");
        fmt::print("  simulated cycles          {:>14}\n", s.total_cycles);
        fmt::print("  simulated bundles         {:>14}   (OS + IC or seq; SC is modelled)\n", s.simulated_bundles);
        fmt::print("  machine wall time         {:>12.2f} s\n", s.wall_seconds);
        fmt::print("  simulated bundles/s       {:>12.1f} M\n", s.bundles_per_second() / 1e6);
        fmt::print("  native wall time          {:>12.3f} s   (1 thread, same prepared scene)\n", native_s);
        fmt::print("  machine / native          {:>12.0f} x\n", s.wall_seconds / native_s);
        fmt::print("  machine cpu time          {:>12.2f} s   (native {:.3f} s)\n", machine_cpu, native_cpu);
        fmt::print("  simulated bundles/cpu s   {:>12.1f} M   compiled runs\n", double(s.simulated_bundles) / machine_cpu / 1e6);
        fmt::print("  simulated bundles/cpu s   {:>12.1f} M   threaded interpreter only\n",
                   double(mi.machine.simulated_bundles) / interp_cpu / 1e6);
        fmt::print("  compiled / interpreted    {:>12.2f} x   (cpu time ratio)\n", interp_cpu / machine_cpu);
        fmt::print("  machine / native, cpu     {:>12.0f} x\n", machine_cpu / native_cpu);
        fmt::print("  images identical          {:>14}\n", native.image.rgb == m.render.image.rgb ? "yes" : "NO");
        fmt::print("  same cycles, both engines {:>14}\n",
                   mi.machine.total_cycles == s.total_cycles && mi.render.image.rgb == m.render.image.rgb ? "yes" : "NO");
        std::fflush(stdout);

        if (!paper_dir.empty()) {
            paper::PaperOptions po;
            po.out_dir = paper_dir;
            const auto t0 = std::chrono::steady_clock::now();
            const paper::PaperRun r = paper::run_paper(po);
            const double wall = seconds_since(t0);
            fmt::print("nesshi paper {}x{}: {} cells run, {} loaded, {:.0f} s = {:.1f} min wall (target < 30 min)\n",
                       po.size, po.size, r.run, r.loaded, wall, wall / 60);
        }
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_machine_render: {}\n", e.what());
        return 1;
    }
    return 0;
}
