// The modulo scheduler on a corpus of loops: per machine, the fraction scheduled at II = MII, the
// mean II / MII, and the scheduling time per loop (and for the 50-operation loops); the counted
// loops first, then the same corpus as `.pipeline while` loops.
// `build/bench_sched [--loops N]`: N random loops per machine (default 200), 5 to 50 compute ops.
#include "args.hpp"

#include "isa/machine.hpp"
#include "sched/pipeline.hpp"
#include "sched/random_loop.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cstring>
#include <string>

using namespace nesshi;

int main(int argc, char** argv) {
    const int loops = int(bench::parse_args(argc, argv, "usage: bench_sched [--loops N]", {"--loops"}).number("--loops", 200));
    using Draw = std::string (*)(std::uint64_t, const isa::Machine&, int);
    for (const auto& [kind, draw] : {std::pair<const char*, Draw>{"counted", sched::random_linear_loop},
                                     std::pair<const char*, Draw>{"while", sched::random_while_loop}}) {
        fmt::print("{} loops\n", kind);
        fmt::print("{:<8} {:>6} {:>9} {:>8} {:>8} {:>12} {:>14}\n", "machine", "loops", "II = MII", "mean", "max", "ms per loop",
                   "ms (50 ops)");
        for (const char* name : {"os", "ic", "os-real", "ic-real"}) {
            const isa::Machine m = isa::load_machine(name);
            int at_bound = 0, scheduled = 0, big = 0;
            double ratio = 0, worst = 0, seconds = 0, big_seconds = 0;
            for (int k = 0; k < loops; ++k) {
                const int ops = 5 + k % 46;
                const std::string text = draw(1000 + static_cast<std::uint64_t>(k), m, ops);
                const auto t0 = std::chrono::steady_clock::now();
                try {
                    const sched::PipelineResult r = sched::pipeline_source(text, "bench.sa", m, {});
                    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                    seconds += s;
                    ++scheduled;
                    at_bound += r.ii == r.mii;
                    const double q = static_cast<double>(r.ii) / r.mii;
                    ratio += q;
                    worst = std::max(worst, q);
                    if (ops == 50) big_seconds += s, ++big;
                } catch (const std::exception& e) {
                    fmt::print(stderr, "{} loop {}: {}\n", name, k, e.what());
                }
            }
            fmt::print("{:<8} {:>6} {:>8.1f}% {:>8.3f} {:>8.3f} {:>12.2f} {:>14.2f}\n", name, scheduled,
                       100.0 * at_bound / std::max(1, scheduled), ratio / std::max(1, scheduled), worst,
                       1e3 * seconds / std::max(1, scheduled), big ? 1e3 * big_seconds / big : 0.0);
        }
    }
    fmt::print("II = MII: the share of loops scheduled at the lower bound max(ResMII, RecMII), loop control included;\n"
               "times: pipeline_source (graph, schedule, registers, code, and the assembler's check of it).\n");
}
