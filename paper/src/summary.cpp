// summary.md: the paper's findings checked against ours (best grid, automatic grid choice, OS/IC
// crossover, M/V against the grid).
#include "report_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

namespace nesshi::paper {

namespace {

constexpr double kIndependentSpread = 0.20; // M/V "roughly independent of the grid": max/min - 1 within this

int paper_best_grid(const std::string& scene) {
    int best = 0;
    double best_v = 0;
    for (const PublishedTimes& p : published_times())
        if (p.scene == paper_scene(scene) && (best == 0 || p.v.value < best_v)) {
            best = p.grid;
            best_v = p.v.value;
        }
    return best;
}

// The first grid (ascending) where OS is heavier than IC, in words. `heavier`: (grid, OS > IC).
std::string crossover(const std::vector<std::pair<int, bool>>& heavier) {
    if (heavier.empty()) return kMissing;
    for (std::size_t i = 0; i < heavier.size(); ++i)
        if (heavier[i].second)
            return i == 0 ? fmt::format("≤ {} (OS heavier at every grid)", heavier[i].first)
                          : fmt::format("{} (IC heavier at {})", heavier[i].first, heavier[i - 1].first);
    return fmt::format("none up to {} (IC heavier)", heavier.back().first);
}

std::string spread_text(const std::vector<double>& v) {
    if (v.size() < 2) return kMissing;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    const double spread = *hi / *lo - 1;
    return fmt::format("{:.0f}% ({})", 100 * spread, spread <= kIndependentSpread ? "roughly independent" : "varies");
}

// "yes"/"no" when the choice can be compared with the measured best, else why not.
std::string agrees(const PaperData& d, const std::map<std::string, int>& choices, const std::string& scene, int ours) {
    auto it = choices.find(scene);
    if (it == choices.end() || !ours) return kMissing;
    if (std::find(d.grids.begin(), d.grids.end(), it->second) == d.grids.end()) return "not in the matrix";
    return it->second == ours ? "yes" : "no";
}

std::string choice(const std::map<std::string, int>& choices, const std::string& scene) {
    auto it = choices.find(scene);
    return it == choices.end() ? kMissing : std::to_string(it->second);
}

void best_grid_section(const PaperData& d, std::string& o) {
    const machine::Model tm = time_model(d);
    o += fmt::format("## Best grid per scene\n\nJudged by model {} time. The paper: mount and tetra are best at 50; "
                     "balls, rings and tree at 100 (of 20, 50, 100). Automatic choices among the matrix's grids: "
                     "**pre-pass**, the paper's suggestion, renders {}x{} through model V at each grid and keeps the "
                     "fastest (about {:.0f}% of the full renders' pixels); **cost model** is rt::choose_grid_resolution "
                     "(`--grid auto`), a native 64x64 render scored with the paper's cycles per voxel step and per "
                     "intersection.\n\n",
                     machine::model_name(tm), d.prepass_size, d.prepass_size,
                     d.size ? 100.0 * d.prepass_size * d.prepass_size / (static_cast<double>(d.size) * d.size) : 0);
    o += fmt::format("| scene | ours: best grid | {} there (Mcycles) | paper: best grid | pre-pass | = ours | cost model "
                     "| = ours |\n|---|---:|---:|---:|---:|---|---:|---|\n",
                     machine::model_name(tm));
    int agree = 0, compared = 0, prepass_agree = 0, prepass_compared = 0;
    for (const std::string& scene : d.scenes) {
        const int ours = best_grid(d, scene, tm), theirs = paper_best_grid(scene);
        const CellRecord* c = ours ? d.find(scene, ours, tm) : nullptr;
        const std::string time =
            !c ? kMissing : format_mcycles(static_cast<double>(tm == machine::Model::S ? s_time(*c) : c->total));
        const std::string pre_same = agrees(d, d.prepass_grid, scene, ours);
        if (pre_same == "yes" || pre_same == "no") {
            ++prepass_compared;
            prepass_agree += pre_same == "yes";
        }
        // Compared only where it means something: the paper's scene, the paper's best grid in our matrix.
        if (ours && theirs && is_paper_scene_size(scene) &&
            std::find(d.grids.begin(), d.grids.end(), theirs) != d.grids.end()) {
            ++compared;
            agree += ours == theirs;
        }
        o += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", scene, ours ? std::to_string(ours) : kMissing,
                         time, theirs ? std::to_string(theirs) : kMissing, choice(d.prepass_grid, scene), pre_same,
                         choice(d.auto_grid, scene), agrees(d, d.auto_grid, scene, ours));
    }
    if (compared) o += fmt::format("\nOurs agrees with the paper's best grid for {} of {} scenes.", agree, compared);
    if (prepass_compared)
        o += fmt::format(" The pre-pass picks the measured best grid for {} of {} scenes.", prepass_agree,
                         prepass_compared);
    o += "\n\n";
}

void crossover_section(const PaperData& d, std::string& o) {
    o += "## OS/IC crossover\n\nThe grid from which the OS stage's load exceeds IC's, model V (ours: load = processing "
         "+ communication; the paper: its Table 2 processing columns, since the printed ratios for tree 20 and 50 "
         "contradict them). OS time grows with the grid, IC time falls; the fastest grid is near the crossover.\n\n"
         "| scene | ours | paper |\n|---|---|---|\n";
    for (const std::string& scene : d.scenes) {
        std::vector<std::pair<int, bool>> ours, theirs;
        for (int g : d.grids)
            if (const CellRecord* v = d.find(scene, g, machine::Model::V))
                ours.emplace_back(g, v->os.load() > v->ic.load());
        for (const PublishedStages& p : published_stages())
            if (p.scene == paper_scene(scene)) theirs.emplace_back(p.grid, p.os > p.ic);
        o += fmt::format("| {} | {} | {} |\n", scene, crossover(ours), crossover(theirs));
    }
    o += "\n";
}

void independence_section(const PaperData& d, std::string& o) {
    o += fmt::format("## Is M/V independent of the grid?\n\nThe VLIW speed-up of the whole machine per grid; the "
                     "spread is max/min - 1, \"roughly independent\" when within {:.0f}%.\n\n",
                     100 * kIndependentSpread);
    o += "| scene | ours M/V | ours spread | paper M/V | paper spread |\n|---|---|---|---|---|\n";
    for (const std::string& scene : d.scenes) {
        std::vector<std::string> ours_text, theirs_text;
        std::vector<double> ours, theirs;
        for (int g : d.grids) {
            const CellRecord *m = d.find(scene, g, machine::Model::M), *v = d.find(scene, g, machine::Model::V);
            if (!m || !v || !v->total) continue;
            ours.push_back(static_cast<double>(m->total) / static_cast<double>(v->total));
            ours_text.push_back(fmt::format("{:.2f} ({})", ours.back(), g));
        }
        for (const PublishedTimes& p : published_times())
            if (p.scene == paper_scene(scene)) {
                theirs.push_back(p.m_over_v.value);
                theirs_text.push_back(fmt::format("{} ({})", format_published(p.m_over_v), p.grid));
            }
        o += fmt::format("| {} | {} | {} | {} | {} |\n", scene,
                         ours.empty() ? kMissing : fmt::format("{}", fmt::join(ours_text, ", ")), spread_text(ours),
                         theirs.empty() ? kMissing : fmt::format("{}", fmt::join(theirs_text, ", ")),
                         spread_text(theirs));
    }
    o += "\n";
}

} // namespace

std::string summary_markdown(const PaperData& d) {
    std::vector<std::string> models;
    for (machine::Model m : d.models) models.push_back(machine::model_name(m));
    std::string o = "# The paper's evaluation, re-run: summary\n\n";
    o += fmt::format("Scenes {}; grids {}; models {}; {}x{} pixels, one PE per run, SPD mode. Tables: table2.md, "
                     "table3.md, table4.md (and .csv); chart: fig6.svg; cells: cells/*.json.\n\n",
                     fmt::join(d.scenes, ", "), fmt::join(d.grids, ", "), fmt::join(models, ", "), d.size, d.size);
    for (const std::string& n : common_notes(d)) o += n + "\n\n";
    best_grid_section(d, o);
    if (has_model(d, machine::Model::V)) crossover_section(d, o);
    // The M cell is there whenever S or M is asked for.
    if ((has_model(d, machine::Model::M) || has_model(d, machine::Model::S)) && has_model(d, machine::Model::V))
        independence_section(d, o);
    return o;
}

} // namespace nesshi::paper
