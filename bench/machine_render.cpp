// Benchmark: the simulated machine's speed. Renders one scene through a model (default: balls,
// model V, grid 50, 512 x 512, one PE on one host thread) and the same prepared scene with the native
// tracer, and prints wall times, simulated bundles per second and their ratio, measured in one run;
// also per CPU second of this process, which a busy shared machine does not inflate, with the
// built-in kernels' compiled runs and again without them (the threaded interpreter).
// --scenes LIST (or `all`: the paper's five) prints one row per scene instead, the table:
// machine / native in CPU time and simulated bundles per CPU-second, compiled and interpreted, and
// (model V, no machine named) a row for the first scene with the IC on a user's description.
// --os-machine / --ic-machine run the stages on a description of the user's (a preset name or a
// TOML file), so its row can be set beside a preset's: its programs, which the build did not
// compile, are compiled at run time during the untimed warm-up render (NESSHI_RUNTIME_COMPILE=wait
// unless the environment says otherwise), so "compiled" is then runs compiled at run time.
// --paper DIR also times the whole `nesshi paper` matrix into DIR (must not hold cells yet, else
// the finished ones are loaded, not timed): the target is under 30 minutes on 2 cores.
// Usage: bench_machine_render [--scene S | --scenes all|S,S,...] [--model V|M|S] [--grid N] [--size N]
//                             [--os-machine M] [--ic-machine M] [--paper DIR]
#include "args.hpp"

#include "isa/machine.hpp"
#include "iss/compiled.hpp"
#include "machine/machine.hpp"
#include "paper/paper.hpp"
#include "rt/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

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

// One scene measured: native once, the machine with compiled runs and on the interpreter alone.
struct Measured {
    double native_s = 0, native_cpu = 0, machine_cpu = 0, interp_cpu = 0, warmup_s = 0;
    nesshi::machine::Result compiled, interpreted;
    bool same_image = false, same_cycles = false;
};

Measured measure(const nesshi::rt::PreparedScene& prep, const nesshi::rt::RenderOptions& opt, const nesshi::machine::Options& mo) {
    using namespace nesshi;
    Measured out;
    const auto t_native = std::chrono::steady_clock::now();
    const double c_native = cpu_seconds();
    const rt::RenderResult native = rt::render_native(prep, opt);
    out.native_s = seconds_since(t_native), out.native_cpu = cpu_seconds() - c_native;
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
    // A process builds the kernels for its machines once, on its first render (the IC's
    // candidates scheduled and measured, seconds on `ic` without the disk cache): an untimed
    // render of a few pixels first, so that both timed runs measure the render alone.
    rt::RenderOptions few = opt;
    few.width = few.height = 4;
    const auto t_warmup = std::chrono::steady_clock::now();
    machine::render(prep, few, mo);
    out.warmup_s = seconds_since(t_warmup);
    out.compiled = machine_run(compiled_default, out.machine_cpu);
    out.interpreted = machine_run(false, out.interp_cpu);
    iss::set_compiled_enabled(compiled_default);
    out.same_image = native.image.rgb == out.compiled.render.image.rgb;
    out.same_cycles = out.interpreted.machine.total_cycles == out.compiled.machine.total_cycles &&
                      out.interpreted.render.image.rgb == out.compiled.render.image.rgb;
    return out;
}

void print_one(const std::string& scene, int size, int grid, const std::string& model, const Measured& r) {
    const nesshi::machine::Stats& s = r.compiled.machine;
    fmt::print("{} {}x{} grid {}, model {}, 1 PE, 1 host thread{}\n", scene, size, size, grid, model,
               nesshi::iss::compiled_enabled() ? "" : " (NESSHI_COMPILED=0: both runs interpreted)");
    fmt::print("  simulated cycles          {:>14}\n", s.total_cycles);
    fmt::print("  simulated bundles         {:>14}   (OS + IC or seq; SC is modelled)\n", s.simulated_bundles);
    fmt::print("  machine wall time         {:>12.2f} s\n", s.wall_seconds);
    fmt::print("  simulated bundles/s       {:>12.1f} M\n", s.bundles_per_second() / 1e6);
    fmt::print("  native wall time          {:>12.3f} s   (1 thread, same prepared scene)\n", r.native_s);
    fmt::print("  machine / native          {:>12.0f} x\n", s.wall_seconds / r.native_s);
    fmt::print("  machine cpu time          {:>12.2f} s   (native {:.3f} s)\n", r.machine_cpu, r.native_cpu);
    fmt::print("  simulated bundles/cpu s   {:>12.1f} M   compiled runs\n", double(s.simulated_bundles) / r.machine_cpu / 1e6);
    fmt::print("  simulated bundles/cpu s   {:>12.1f} M   threaded interpreter only\n",
               double(r.interpreted.machine.simulated_bundles) / r.interp_cpu / 1e6);
    fmt::print("  compiled / interpreted    {:>12.2f} x   (cpu time ratio)\n", r.interp_cpu / r.machine_cpu);
    fmt::print("  machine / native, cpu     {:>12.0f} x\n", r.machine_cpu / r.native_cpu);
    fmt::print("  images identical          {:>14}\n", r.same_image ? "yes" : "NO");
    fmt::print("  same cycles, both engines {:>14}\n", r.same_cycles ? "yes" : "NO");
    fmt::print("  warm-up render (4 x 4)    {:>12.2f} s   (kernels built, runs compiled at run time unless cached)\n",
               r.warmup_s);
}

} // namespace

int main(int argc, char** argv) {
    using namespace nesshi;
    using namespace nesshi::rt;
    const char* usage = "usage: bench_machine_render [--scene S | --scenes all|S,S,...] [--model V|M|S] [--grid N] [--size N] "
                        "[--os-machine M] [--ic-machine M] [--paper DIR]";
    const bench::Args args = bench::parse_args(
        argc, argv, usage, {"--scene", "--scenes", "--model", "--grid", "--size", "--os-machine", "--ic-machine", "--paper"});
    const std::string scene = args.text("--scene", "balls"), model = args.text("--model", "V"),
                      paper_dir = args.text("--paper", ""), scenes = args.text("--scenes", "");
    if (args.values.count("--scene") && args.values.count("--scenes")) {
        fmt::print(stderr, "bench_machine_render: --scene or --scenes, not both\n{}\n", usage);
        return 2;
    }
    const int grid = int(args.number("--grid", 50)), size = int(args.number("--size", 512));
    if (!std::getenv("NESSHI_RUNTIME_COMPILE")) iss::set_runtime_compile_mode(iss::RuntimeCompile::Wait);
    try {
        machine::Options mo;
        if (!machine::parse_model(model, mo.model)) throw std::runtime_error("unknown model " + model);
        mo.threads = 1;
        mo.os_machine = args.text("--os-machine", "os");
        mo.ic_machine = args.text("--ic-machine", "ic");
        RenderOptions opt;
        opt.width = opt.height = size;
        opt.threads = 1;
        if (scenes.empty()) {
            print_one(scene, size, grid, model, measure(prepare(load_scene(scene), grid), opt, mo));
        } else {
            std::vector<std::string> list;
            const std::string names = scenes == "all" ? "balls,mount,rings,tetra,tree" : scenes;
            for (std::size_t at = 0; at <= names.size();) {
                const std::size_t comma = std::min(names.find(',', at), names.size());
                std::string name = names.substr(at, comma - at);
                name.erase(0, name.find_first_not_of(' '));
                name.erase(name.find_last_not_of(' ') + 1);
                if (!name.empty()) list.push_back(name);
                at = comma + 1;
            }
            const std::string stages = mo.model == machine::Model::V
                                           ? fmt::format("OS {}, IC {}", mo.os_machine.reference(), mo.ic_machine.reference())
                                           : "seq";
            fmt::print("{}x{} grid {}, model {} on {}, 1 PE, 1 host thread; CPU time of this process\n", size, size, grid, model,
                       stages);
            fmt::print("{:<8} {:>14} {:>16} {:>22} {:>24} {:>14} {:>9}\n", "scene", "machine/native", "sim. bundles",
                       "M bundles/cpu s, comp.", "M bundles/cpu s, interp.", "comp./interp.", "identical");
            double first_warmup = -1;
            auto row = [&](const std::string& label, const std::string& sc, const machine::Options& on) {
                const Measured r = measure(prepare(load_scene(sc), grid), opt, on);
                if (first_warmup < 0) first_warmup = r.warmup_s;
                const machine::Stats& s = r.compiled.machine;
                fmt::print("{:<8} {:>13.1f}x {:>16} {:>22.1f} {:>24.1f} {:>13.2f}x {:>9}\n", label, r.machine_cpu / r.native_cpu,
                           s.simulated_bundles, double(s.simulated_bundles) / r.machine_cpu / 1e6,
                           double(r.interpreted.machine.simulated_bundles) / r.interp_cpu / 1e6, r.interp_cpu / r.machine_cpu,
                           r.same_image && r.same_cycles ? "yes" : "NO");
                std::fflush(stdout);
            };
            for (const std::string& sc : list) row(sc, sc, mo);
            // A user's description beside the presets (the table has this row): its kernels are
            // scheduled for it and its runs compiled at run time (in the warm-up, under `wait`).
            const bool user_row = mo.model == machine::Model::V && !args.values.count("--os-machine") &&
                                  !args.values.count("--ic-machine") && !list.empty();
            if (user_row) {
                machine::Options user = mo;
                user.ic_machine = kbuild::StageMachine(
                    isa::parse_machine("inherits = \"ic\"\nname = \"user-ic\"\n[latency]\nfadd = 2\n", "user-ic.toml"), "user-ic");
                row(list.front() + "*", list.front(), user);
                machine::Options real = mo; // latencies and a branch penalty in both stages
                real.os_machine = "os-real";
                real.ic_machine = "ic-real";
                row(list.front() + "**", list.front(), real);
                fmt::print("*: the IC on a user's description (ic with 2-cycle fadd): kernels scheduled for it, runs compiled at "
                           "run time\n**: os-real and ic-real (multi-cycle units, a branch bubble): the IC's runs compiled at run "
                           "time\n");
            }
            fmt::print("warm-up render of the first scene: {:.1f} s wall (kernels built, runs compiled at run time unless cached)\n",
                       first_warmup);
        }
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
