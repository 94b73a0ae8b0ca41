// Numbers derived from cells that the tables, the chart and the summary share.
#include "paper/paper.hpp"

#include "rt/spd.hpp"

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

double scale_to_paper(int size) {
    const double f = 512.0 / static_cast<double>(size);
    return f * f;
}

std::string paper_scene(const std::string& scene) {
    try {
        if (auto n = rt::parse_spd_name(scene); n && n->name != "gears") return n->name;
    } catch (const std::invalid_argument&) {
    }
    return "";
}

bool is_paper_scene_size(const std::string& scene) {
    try {
        auto n = rt::parse_spd_name(scene);
        return n && n->name != "gears" && (n->size == 0 || n->size == rt::spd_default_size(n->name));
    } catch (const std::invalid_argument&) {
        return false;
    }
}

std::array<int, 3> load_ratio(const CellRecord& v) {
    const double loads[3] = {static_cast<double>(v.os.load()), static_cast<double>(v.ic.load()),
                             static_cast<double>(v.sc.load())};
    const double smallest = *std::min_element(std::begin(loads), std::end(loads));
    if (smallest <= 0) return {0, 0, 0};
    std::array<int, 3> r{};
    for (std::size_t i = 0; i < 3; ++i) r[i] = static_cast<int>(std::lround(loads[i] / smallest));
    return r;
}

std::uint64_t s_time(const CellRecord& m) { return m.s_cycles ? m.s_cycles : m.os.load() + m.ic.load() + m.sc.load(); }

int best_grid(const PaperData& d, const std::string& scene, machine::Model m) {
    int best = 0;
    std::uint64_t best_time = 0;
    for (int g : d.grids) { // ascending: a tie goes to the smaller grid
        const CellRecord* c = d.find(scene, g, m);
        if (!c) continue;
        const std::uint64_t t = m == machine::Model::S ? s_time(*c) : c->total;
        if (best == 0 || t < best_time) {
            best = g;
            best_time = t;
        }
    }
    return best;
}

machine::Model time_model(const PaperData& d) {
    for (machine::Model m : {machine::Model::V, machine::Model::M, machine::Model::S})
        if (std::find(d.models.begin(), d.models.end(), m) != d.models.end()) return m;
    return machine::Model::V;
}

} // namespace nesshi::paper
