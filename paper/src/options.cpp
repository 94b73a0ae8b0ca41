// The options' checks and the matrix they ask for.
#include "paper/paper.hpp"

#include "rt/spd.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace nesshi::paper {

namespace {
void validate_scene(const std::string& scene) {
    try {
        if (rt::parse_spd_name(scene) || std::filesystem::is_regular_file(scene)) return;
    } catch (const std::invalid_argument& e) { // a built-in name with a bad size suffix
        throw PaperError(e.what());
    }
    throw PaperError(fmt::format(
        "unknown scene '{}' (built-in: balls mount rings tetra tree gears, NAME:SIZE, or an NFF file)", scene));
}
} // namespace

void validate(const PaperOptions& o) {
    if (o.size < 1 || o.size > 16384) throw PaperError(fmt::format("bad size {} (1 to 16384)", o.size));
    if (o.scenes.empty()) throw PaperError("no scene");
    for (const std::string& s : o.scenes) validate_scene(s);
    if (o.grids.empty()) throw PaperError("no grid");
    for (int g : o.grids)
        if (g < 1 || g > 512) throw PaperError(fmt::format("bad grid {} (1 to 512 voxels per side)", g));
    if (o.models.empty()) throw PaperError("no model");
    if (o.threads < 0) throw PaperError(fmt::format("bad thread count {}", o.threads));
    if (o.shards < 1 || o.shard < 1 || o.shard > o.shards)
        throw PaperError(fmt::format("bad shard {}/{} (1/N to N/N)", o.shard, o.shards));
}

bool wants(const PaperOptions& o, machine::Model m) {
    return std::find(o.models.begin(), o.models.end(), m) != o.models.end();
}

std::vector<CellKey> matrix_cells(const PaperOptions& o) {
    std::vector<int> grids = o.grids;
    std::sort(grids.begin(), grids.end());
    grids.erase(std::unique(grids.begin(), grids.end()), grids.end());
    std::vector<CellKey> cells;
    for (const std::string& scene : o.scenes)
        for (int g : grids) {
            if (wants(o, machine::Model::V)) cells.push_back({scene, g, machine::Model::V, o.size});
            if (wants(o, machine::Model::S) || wants(o, machine::Model::M))
                cells.push_back({scene, g, machine::Model::M, o.size});
        }
    return cells;
}

} // namespace nesshi::paper
