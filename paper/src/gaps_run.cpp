// The gap attribution's inputs: native renders (the SPD view and each view hypothesis) and our model V
// cells; the renders are fast (the whole 512 x 512 matrix takes a few minutes), the cells are read.
#include "paper/gaps.hpp"
#include "paper/paper.hpp"

#include "base/read_file.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace nesshi::paper {

namespace {

WorkCounts render_counts(rt::Scene scene, int grid, const GapsOptions& o) {
    const rt::PreparedScene prep = rt::prepare(std::move(scene), grid);
    rt::RenderOptions ro;
    ro.width = ro.height = o.size;
    ro.threads = o.threads;
    return work_counts(rt::render_native(prep, ro).stats);
}

OursCell load_ours(const std::string& scene, int grid, const GapsOptions& o) {
    const CellKey key{scene, grid, machine::Model::V, o.size};
    const std::string file = (std::filesystem::path(o.cells_dir) / cell_file_name(key)).string();
    if (!std::filesystem::exists(file))
        throw PaperError(fmt::format("{}: no model V cell (run `nesshi paper --out DIR` first)", file));
    const CellRecord c = parse_cell(key, base::read_file(file), file);
    OursCell ours;
    ours.os = static_cast<double>(c.os.processing);
    ours.ic = static_cast<double>(c.ic.processing);
    return ours;
}

// A smaller image's counts and cycles, scaled to the paper's 512 x 512 like Table 2's (scale_to_paper).
void scale(OursCell& c, double s) {
    c.os *= s;
    c.ic *= s;
    for (double* v : {&c.counts.eye_rays, &c.counts.rays, &c.counts.steps, &c.counts.visits, &c.counts.triangle_tests,
                      &c.counts.quadric_tests, &c.counts.quadric_two_roots})
        *v *= s;
}

} // namespace

std::vector<GapRow> run_gaps(const GapsOptions& o) {
    auto say = [&](const std::string& line) {
        if (o.progress) o.progress(line);
    };
    std::vector<GapRow> rows;
    for (const std::string& scene : o.scenes)
        for (int grid : o.grids) {
            OursCell ours = load_ours(scene, grid, o);
            const rt::Scene sc = rt::load_scene(scene);
            say(fmt::format("gaps: {} grid {}: native render at {}x{}", scene, grid, o.size, o.size));
            ours.counts = render_counts(sc, grid, o);
            const double s = scale_to_paper(o.size);
            scale(ours, s);
            std::vector<HypothesisResult> hs{two_roots_hypothesis(ours.counts), init_every_ray_hypothesis(ours.counts)};
            for (const SceneVariant& v : scene_variants()) {
                if (v.scene != scene) continue;
                say(fmt::format("gaps: {} grid {}: {}", scene, grid, v.name()));
                OursCell alt;
                alt.counts = render_counts(apply_variant(sc, v), grid, o);
                scale(alt, s);
                const WorkCounts& w = alt.counts;
                hs.push_back({v.name(), os_cycles(w, paper_prices()), ic_cycles(w, paper_prices()), w});
            }
            rows.push_back(attribute(scene, grid, ours, std::move(hs)));
        }
    return rows;
}

} // namespace nesshi::paper
