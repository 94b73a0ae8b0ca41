// The modulo scheduler on a corpus of loops: per machine, the fraction scheduled at II = MII, the
// mean II / MII, and the scheduling time per loop (and for the 50-operation loops); the counted
// loops first, then the same corpus as `.pipeline while` loops. With `--trip T`, the counted
// loops again with `.trip T`: the whole run per iteration at T trips against the MII, of the first
// schedule found (the rule without .trip) and of the one chosen by whole-run cycles.
// `build/bench_sched [--loops N] [--trip T]`: N random loops per machine (default 200), 5 to 50 compute ops.
// `build/bench_sched --corpus DIR`: instead, each loop of DIR/*.sa (bench/corpus: loops written the
// way users write them) on each preset: its bounds, II, stages, copies (register copies x kernel repeats), registers, and its whole
// run per iteration at its `.trip` count (a while loop: its kernel per iteration) against the MII.
#include "args.hpp"

#include "isa/machine.hpp"
#include "sched/pipeline.hpp"
#include "sched/random_loop.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <string>

using namespace nesshi;

namespace {

// The counted corpus with `.trip T`: whole-run cycles per iteration over the MII, and the share
// within MII x 1.10 (+ 0.25 on a machine with a taken-branch bubble), first found and chosen.
void whole_runs(int loops, int trip) {
    fmt::print("counted loops with .trip {} (whole run per iteration / MII)\n", trip);
    fmt::print("{:<8} {:>6} {:>12} {:>12} {:>10} {:>10} {:>8} {:>12}\n", "machine", "loops", "first ok", "chosen ok",
               "first", "chosen", "changed", "ms per loop");
    for (const char* name : {"os", "ic", "os-real", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        int n = 0, first_ok = 0, chosen_ok = 0, changed = 0;
        double first = 0, chosen = 0, seconds = 0;
        for (int k = 0; k < loops; ++k) {
            std::string text = sched::random_linear_loop(1000 + static_cast<std::uint64_t>(k), m, 5 + k % 46);
            const std::size_t at = text.find('\n', text.find(".pipeline r9")) + 1;
            text.insert(at, fmt::format("        .trip {}\n", trip));
            const auto t0 = std::chrono::steady_clock::now();
            try {
                const sched::PipelineResult r = sched::pipeline_source(text, "bench.sa", m, {});
                seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                const sched::TripChoice& c = *r.loops.at(0).trip;
                const double bound = 1.10 * r.mii + (m.branch_penalty > 0 ? 0.25 : 0.0);
                const double f = static_cast<double>(c.first.cycles) / trip, h = static_cast<double>(c.chosen.cycles) / trip;
                ++n;
                first_ok += f <= bound;
                chosen_ok += h <= bound;
                first += f / r.mii;
                chosen += h / r.mii;
                changed += c.chosen.cycles != c.first.cycles;
            } catch (const std::exception& e) {
                fmt::print(stderr, "{} loop {}: {}\n", name, k, e.what());
            }
        }
        const int d = std::max(1, n);
        fmt::print("{:<8} {:>6} {:>11.1f}% {:>11.1f}% {:>10.3f} {:>10.3f} {:>8} {:>12.2f}\n", name, n, 100.0 * first_ok / d,
                   100.0 * chosen_ok / d, first / d, chosen / d, changed, 1e3 * seconds / d);
    }
    fmt::print("ok: whole run within MII x 1.10 (+0.25 with a branch bubble); first: the first schedule found (the rule\n"
               "without .trip), costed as its code with .trip; chosen: the one .trip takes; changed: loops where they differ.\n");
}

// The corpus: every loop on every preset. The files' data sit at 0x1000 (the OS SRAM); on a
// machine whose first memory starts elsewhere they move to its base + 0x100, as the random loops do.
void corpus(const std::string& dir) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".sa") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    fmt::print("{:<14} {:<8} {:>4} {:>6} {:>6} {:>5} {:>4} {:>6} {:>6} {:>5} {:>9} {:>8} {:>4} {:>8}\n", "loop", "machine", "ops",
               "ResMII", "RecMII", "bound", "II", "stages", "copies", "regs", "per iter", "/ MII", "ok", "ms");
    for (const char* name : {"os", "os-real", "ic", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        int n = 0, ok = 0, at_mii = 0, at_bound = 0;
        for (const auto& f : files) {
            std::ifstream in(f);
            std::stringstream ss;
            ss << in.rdbuf();
            std::string text = ss.str();
            if (const std::size_t at = text.find(".data 0x1000"); at != std::string::npos)
                text.replace(at, 12, fmt::format(".data 0x{:x}", m.memories.front().base + 0x100));
            const std::string loop = f.stem().string();
            const auto t0 = std::chrono::steady_clock::now();
            try {
                const sched::PipelineResult r = sched::pipeline_source(text, f.string(), m, {});
                const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                const sched::LoopSummary& l = r.loops.at(0);
                const double per = l.trip ? static_cast<double>(l.trip->chosen.cycles) / l.trip->expected
                                          : static_cast<double>(l.unroll * l.groups * l.ii + static_cast<int>(m.branch_penalty)) /
                                                (l.unroll * l.groups);
                const bool good = per <= 1.10 * l.proven_mii + (m.branch_penalty > 0 ? 0.25 : 0.0);
                ++n;
                ok += good;
                at_mii += l.ii == l.mii;
                at_bound += l.ii == l.proven_mii;
                const std::size_t ops = std::count(text.begin() + static_cast<std::ptrdiff_t>(text.find(".pipeline")),
                                                   text.begin() + static_cast<std::ptrdiff_t>(text.find(".endpipeline")), '\n');
                const std::string copies = l.groups == 1 ? fmt::format("{}", l.unroll) : fmt::format("{}x{}", l.unroll, l.groups);
                fmt::print("{:<14} {:<8} {:>4} {:>6} {:>6} {:>5} {:>4} {:>6} {:>6} {:>5} {:>9.2f} {:>8.3f} {:>4} {:>8.1f}\n", loop, name,
                           ops, l.res_mii, l.rec_mii, l.proven_mii, l.ii, l.stages, copies, r.scratch.size(), per, per / l.mii,
                           good ? "yes" : "no", ms);
            } catch (const std::exception& e) {
                fmt::print("{:<14} {:<8} failed: {}\n", loop, name, std::string(e.what()).substr(0, 120));
            }
        }
        fmt::print("{:<14} {:<8} {} of {} within bound x 1.10{}, {} at II = MII, {} at II = bound\n", "", name, ok, n,
                   m.branch_penalty > 0 ? " + 0.25" : "", at_mii, at_bound);
    }
    fmt::print("per iter: the whole run per iteration at the loop's .trip count (a while loop: its kernel per iteration,\n"
               "bubble included); ops: the region's lines; regs: registers the tool allocated; ms: pipeline_source;\n"
               "bound: the least II with a modulo schedule, as far as proven: MII, or above it where the constraint model\n"
               "proves that none exists (nesshi pipeline's report says why); ok: per iter within bound x 1.10 (+0.25).\n");
}

// `--exact S`: the random counted loops the heuristic leaves above their MII, again with
// `--exact S`, on each preset: how many are proven optimal, improved, or left undecided, and
// the time each took.
void exact_runs(int loops, double seconds) {
    fmt::print("counted loops above their MII, with --exact {}\n", seconds);
    fmt::print("{:<8} {:>6} {:>8} {:>9} {:>10} {:>10} {:>10}\n", "machine", "above", "proven", "improved", "undecided",
               "mean s", "max s");
    for (const char* name : {"os", "ic", "os-real", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        int above = 0, proven = 0, improved = 0, undecided = 0;
        double total = 0, worst = 0;
        for (int k = 0; k < loops; ++k) {
            const std::string text = sched::random_linear_loop(1000 + static_cast<std::uint64_t>(k), m, 5 + k % 46);
            try {
                const sched::PipelineResult plain = sched::pipeline_source(text, "bench.sa", m, {});
                if (plain.ii == plain.mii) continue;
                ++above;
                sched::PipelineOptions o;
                o.exact_seconds = seconds;
                const auto t0 = std::chrono::steady_clock::now();
                const sched::PipelineResult r = sched::pipeline_source(text, "bench.sa", m, o);
                const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                total += s;
                worst = std::max(worst, s);
                improved += r.ii < plain.ii;
                if (r.report.find("II proven optimal") != std::string::npos) ++proven;
                else ++undecided;
            } catch (const std::exception& e) {
                fmt::print(stderr, "{} loop {}: {}\n", name, k, e.what());
            }
        }
        fmt::print("{:<8} {:>6} {:>8} {:>9} {:>10} {:>10.2f} {:>10.2f}\n", name, above, proven, improved, undecided,
                   total / std::max(1, above), worst);
    }
    fmt::print("proven: the II taken is proven optimal (none below it has a modulo schedule that assembles); improved: a\n"
               "lower II than the heuristic's; undecided: the time ran out first.\n");
}

} // namespace

int main(int argc, char** argv) {
    const bench::Args args = bench::parse_args(argc, argv, "usage: bench_sched [--loops N] [--trip T] [--corpus DIR] [--exact S]",
                                               {"--loops", "--trip", "--corpus", "--exact"});
    if (const std::string dir = args.text("--corpus", ""); !dir.empty()) {
        corpus(dir);
        return 0;
    }
    const int loops = int(args.number("--loops", 200)), trip = int(args.number("--trip", 0));
    if (const double exact = args.number("--exact", 0); exact > 0) {
        exact_runs(loops, exact);
        return 0;
    }
    using Draw = std::string (*)(std::uint64_t, const isa::Machine&, int);
    for (const auto& [kind, draw] : {std::pair<const char*, Draw>{"counted", sched::random_linear_loop},
                                     std::pair<const char*, Draw>{"while", sched::random_while_loop}}) {
        fmt::print("{} loops\n", kind);
        fmt::print("{:<8} {:>6} {:>9} {:>8} {:>8} {:>8} {:>12} {:>14}\n", "machine", "loops", "II = MII", "mean", "max", "stages",
                   "ms per loop", "ms (50 ops)");
        for (const char* name : {"os", "ic", "os-real", "ic-real"}) {
            const isa::Machine m = isa::load_machine(name);
            int at_bound = 0, scheduled = 0, big = 0;
            double ratio = 0, worst = 0, seconds = 0, big_seconds = 0, stages = 0;
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
                    stages += r.stages;
                    worst = std::max(worst, q);
                    if (ops == 50) big_seconds += s, ++big;
                } catch (const std::exception& e) {
                    fmt::print(stderr, "{} loop {}: {}\n", name, k, e.what());
                }
            }
            fmt::print("{:<8} {:>6} {:>8.1f}% {:>8.3f} {:>8.3f} {:>8.2f} {:>12.2f} {:>14.2f}\n", name, scheduled,
                       100.0 * at_bound / std::max(1, scheduled), ratio / std::max(1, scheduled), worst, stages / std::max(1, scheduled),
                       1e3 * seconds / std::max(1, scheduled), big ? 1e3 * big_seconds / big : 0.0);
        }
    }
    if (trip > 0) whole_runs(loops, trip);
    fmt::print("II = MII: the share of loops scheduled at the lower bound max(ResMII, RecMII), loop control included;\n"
               "stages: the mean stage count (iterations in flight);\n"
               "times: pipeline_source (graph, schedule, registers, code, and the assembler's check of it).\n");
}
