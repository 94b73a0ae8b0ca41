// `nesshi scene`: `info` (counts, view, bounds, grid sizes against the machine's memories) and `gen`.
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "ranges.hpp"

#include "base/write_file.hpp"

#include "kernels/abi.hpp"
#include "machine/memory_report.hpp"
#include "rt/grid.hpp"
#include "rt/scene.hpp"
#include "rt/shapes.hpp"
#include "rt/render.hpp"
#include "rt/spd.hpp"

#include <fmt/format.h>


namespace nesshi::cli {

namespace {

void scene_info(const std::string& what, const std::vector<int>& grids) {
    try {
        for (int n : grids) rt::check_grid_resolution(n); // before any work, as render does
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    rt::Scene s = rt::load_scene(what);
    rt::SceneCounts c = rt::count(s);
    rt::Box b = rt::scene_bounds(s);
    fmt::print("scene {}\n", s.name);
    fmt::print("primitives {}: {} spheres, {} cylinders, {} cones, {} polygons, {} patches ({} triangles)\n",
               c.total(), c.spheres, c.cylinders, c.cones, c.polygons, c.patches, c.triangles);
    fmt::print("lights {}, materials {}, reflective primitives {}, transmitting primitives {}\n", s.lights.size(),
               s.materials.size(), c.reflective, c.transmitting);
    const rt::View& v = s.view;
    fmt::print("view from ({:g} {:g} {:g}) at ({:g} {:g} {:g}) up ({:g} {:g} {:g}) angle {:g} hither {:g} "
               "resolution {}x{}\n",
               v.from.x, v.from.y, v.from.z, v.at.x, v.at.y, v.at.z, v.up.x, v.up.y, v.up.z, v.angle, v.hither, v.width,
               v.height);
    fmt::print("background {:g} {:g} {:g}\n", s.background.r, s.background.g, s.background.b);
    if (!b.empty())
        fmt::print("bounding box ({:g} {:g} {:g}) - ({:g} {:g} {:g})\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    if (grids.empty()) return;
    rt::ShapeSet set = rt::build_shapes(s);
    // The same count as the memory lines' "records": every shape's record plus the END record.
    fmt::print("shape records {} + the END record ({} bytes in IC memory, {} B each)\n", set.shapes.size(),
               kernels::abi::ic_records_bytes(set.shapes.size()), kernels::kShapeWords * 4);
    for (int n : grids) {
        rt::Grid g = rt::build_grid(s, set, n);
        fmt::print("{}{}", rt::format_grid(g), machine::memory_report(g, set.shapes.size()).text());
    }
}

} // namespace

void add_scene(CLI::App& app) {
    auto* cmd = app.add_subcommand("scene", "Inspect or generate SPD/NFF scenes");
    cmd->require_subcommand(1);

    auto* info = cmd->add_subcommand("info", "Counts, view, bounds, and grid memory footprint of a scene");
    auto file = std::make_shared<std::string>();
    auto grids = std::make_shared<std::vector<int>>(std::vector<int>{20, 50, 100});
    auto no_grid = std::make_shared<bool>(false);
    info->add_option("scene", *file, "NFF file or built-in name (balls mount rings tetra tree gears, NAME:SIZE)")->required();
    auto* grid_opt = info->add_option("--grid", *grids, "grid resolutions to report (0 = auto)")->delimiter(',');
    info->add_flag("--no-grid", *no_grid, "skip the grid report")->excludes(grid_opt);
    info->callback([=] {
        scene_info(*file, *no_grid ? std::vector<int>{} : *grids);
    });

    auto* gen = cmd->add_subcommand("gen", "Write a built-in SPD scene as NFF");
    auto name = std::make_shared<std::string>();
    auto size = std::make_shared<int>(0);
    auto out = std::make_shared<std::string>();
    gen->add_option("name", *name, "balls mount rings tetra tree gears")->required();
    gen->add_option("-s,--size", *size, "size factor (default: the generator's, the paper's scenes)")
        ->check(between(1, 20));
    gen->add_option("-o,--output", *out, "output file (default, or '-': stdout)");
    gen->callback([=] {
        check_output(*out);
        std::string nm = *name;
        int sz = *size;
        if (auto p = rt::parse_spd_name(nm)) {
            nm = p->name;
            if (sz == 0) sz = p->size;
        }
        std::string text = rt::generate_spd(nm, sz);
        if (out->empty()) fmt::print("{}", text);
        else base::write_file(*out, text);
    });
}

} // namespace nesshi::cli
