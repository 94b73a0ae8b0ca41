// Benchmark: the native float32 renderer on the paper's five scenes at grid 20/50/100 (the baseline
// the simulator's speed is compared with). Prints seconds and rays per second; not a test.
// Usage: bench_native_render [--size N] [--threads N] [--grids 20,50,100] [scene ...]
#include "args.hpp"

#include "rt/render.hpp"
#include "rt/spd.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    using namespace nesshi::rt;
    const nesshi::bench::Args args = nesshi::bench::parse_args(
        argc, argv, "usage: bench_native_render [--size N] [--threads N] [--grids 20,50,100] [scene ...]",
        {"--size", "--threads", "--grids"}, true);
    int size = int(args.number("--size", 512));
    const int threads = int(args.number("--threads", 0));
    std::vector<int> grids;
    std::stringstream ss(args.text("--grids", "20,50,100"));
    for (std::string g; std::getline(ss, g, ',');) grids.push_back(std::atoi(g.c_str()));
    std::vector<std::string> scenes = args.positionals;
    if (scenes.empty()) scenes = spd_names();
    if (size < 1) size = 512;
    fmt::print("native renderer, {}x{}, SPD mode, threads {}\n", size, size, threads ? std::to_string(threads) : "all");
    fmt::print("{:<8} {:>5} {:>9} {:>9} {:>12} {:>12} {:>14}\n", "scene", "grid", "setup s", "trace s", "rays",
               "Mrays/s", "tests/ray");
    for (const std::string& s : scenes) {
        Scene scene = load_scene(s);
        for (int g : grids) {
            PreparedScene p = prepare(scene, g);
            RenderOptions o;
            o.width = o.height = size;
            o.threads = threads;
            RenderResult r = render_native(p, o);
            const RayStats& rs = r.stats.rays;
            const std::uint64_t rays = rs.eye_rays + rs.shadow_rays + rs.reflection_rays + rs.refraction_rays;
            std::uint64_t tests = 0;
            for (const TraceCounters& c : r.stats.traversal) tests += c.triangle_tests + c.quadric_tests;
            fmt::print("{:<8} {:>5} {:>9.3f} {:>9.3f} {:>12} {:>12.3f} {:>14.1f}\n", s, g, r.stats.setup_seconds,
                       r.stats.trace_seconds, rays, static_cast<double>(rays) / r.stats.trace_seconds / 1e6,
                       static_cast<double>(tests) / static_cast<double>(rays));
            std::fflush(stdout);
        }
    }
    return 0;
}
