// `nesshi paper gaps`: the absolute gaps of our Table 2 against the paper's, attributed per scene x
// grid to kernel speed (our cycles per step against the paper's), workload (what the native renderer
// counts: voxel steps, VISITs, intersection tests) and the hypotheses that change the workload or
// its pricing; what no hypothesis explains is reported as unexplained.
//
//   paper::GapRow row = paper::attribute(paper_row, ours, counts, hypotheses); // one scene x grid
//   fmt::print("{}", paper::gaps_markdown(rows));                             // the tables
//   std::ofstream("gaps.svg") << paper::gaps_svg(rows);                        // the chart
//
// Pricing a workload at the paper's step costs (PAPER.md): OS = 60 per eye ray (initialisation,
// "initial rays only") + 11 per voxel step; IC = (40 + 10) per triangle test + (50 + 11) per quadric
// test. FIFO loads and stores (25 each) are communication, which Table 2's processing columns leave
// out. Factors multiply: paper / ours = kernel x workload x unexplained.
#pragma once

#include "kernels/paper_figures.hpp"
#include "paper/published.hpp"
#include "rt/render.hpp"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::paper {

// The native renderer's counts for one render, summed over the ray kinds.
struct WorkCounts {
    double eye_rays = 0, rays = 0, steps = 0, visits = 0;
    double triangle_tests = 0, quadric_tests = 0, quadric_two_roots = 0;
};
WorkCounts work_counts(const rt::RenderStats& s);

// Cycles per unit of work. paper_prices(): the paper's step costs. A quadric test whose quadratic
// has no two distinct real roots costs `quadric_miss`: the paper gives 50 + 11 only "when the
// quadratic has two distinct real roots", so the two-roots hypothesis prices a miss at its shape
// load alone (11), the least the paper's text allows.
struct Prices {
    double init = kernels::kPaper.dda_init, step = kernels::kPaper.dda_step_vliw;
    double triangle = kernels::kPaper.triangle + kernels::kPaper.triangle_load;
    double quadric = kernels::kPaper.quadric + kernels::kPaper.quadric_load, quadric_miss = quadric;
};
Prices paper_prices();
double os_cycles(const WorkCounts& w, const Prices& p); // init x eye rays + step x voxel steps
double ic_cycles(const WorkCounts& w, const Prices& p); // triangle, two-root and other quadric tests

// A variant of the workload or of its pricing, and the cycles it predicts at the paper's prices.
struct HypothesisResult {
    std::string name; // "view 22.5", "two roots"
    double os = 0, ic = 0;
    WorkCounts counts;
};

// Our run of one scene x grid: model V processing cycles (a paper cell) and the native counts.
struct OursCell {
    double os = 0, ic = 0;
    WorkCounts counts;
};

struct GapRow {
    std::string scene;
    int grid = 0;
    double paper_os = 0, paper_ic = 0, paper_os_comm = 0, paper_ic_comm = 0; // cycles
    OursCell ours;
    // What the paper's cycles imply at its own step costs, beside our counts.
    double implied_steps = 0;  // (OS - 60 x eye rays) / 11
    double implied_visits = 0; // IC communication / 25: one overlapped FIFO load + store per VISIT
    double implied_tests = 0;  // IC / the mean price of a test in our mix of triangles and quadrics
    // Our counts priced at the paper's step costs, and the factors.
    double os_priced = 0, ic_priced = 0;
    double os_kernel = 0, ic_kernel = 0; // priced / our cycles: how much faster our kernels are
    std::vector<HypothesisResult> hypotheses;
    // The adopted hypothesis per stage (gap_adoptions()), nullopt: none; explained = the cycles the
    // adopted hypothesis predicts (os_priced without one), unexplained = paper / explained.
    std::optional<std::string> os_adopted, ic_adopted;
    double os_explained = 0, ic_explained = 0;
    double os_unexplained() const { return paper_os / os_explained; }
    double ic_unexplained() const { return paper_ic / ic_explained; }
};

// Which hypothesis the attribution adopts for a scene's stage, and why in one line; the runs that
// back each are in docs/paper-512/gaps.md.
struct GapAdoption {
    std::string_view scene;
    std::string_view stage; // "OS" or "IC"
    std::string_view hypothesis;
    std::string_view reason;
};
std::span<const GapAdoption> gap_adoptions();

// One row from the paper's numbers, ours and the hypotheses' results (already priced). Throws
// PaperError when the paper has no such scene x grid or a count is zero where it divides.
GapRow attribute(std::string_view scene, int grid, const OursCell& ours, std::vector<HypothesisResult> hypotheses);

// The pricing hypotheses (no render needed). "two roots": a quadric test without two distinct real
// roots costs its shape load alone (11). "init every ray": OS initialises every new ray (eye, shadow,
// secondary: 60 each), not only the eye rays; return rays from IC continue without it.
HypothesisResult two_roots_hypothesis(const WorkCounts& w);
HypothesisResult init_every_ray_hypothesis(const WorkCounts& w);

// Least squares of the paper's cycles against one of our counts over a scene's grids: the paper's
// cycles per counted unit (slope) and a fixed part (intercept). Needs two grids or more.
struct LineFit {
    double slope = 0, intercept = 0;
};
LineFit fit_line(std::span<const double> x, std::span<const double> y);

std::string gaps_markdown(std::span<const GapRow> rows); // the tables of gaps.md's "generated" part
std::string gaps_json(std::span<const GapRow> rows);
std::string gaps_csv(std::span<const GapRow> rows);
std::string gaps_svg(std::span<const GapRow> rows); // log-scale bars: ours, explained, paper

// The workload hypotheses that need a render of their own: the scene changed, then rendered. A view
// angle (tetra at 22.5 degrees, half the SPD's 45), or the floor (the polygon of largest extent)
// scaled about the origin in x and y, which narrows the grid that the floor stretches.
struct SceneVariant {
    enum class Kind { view_angle, floor_scale };
    std::string_view scene;
    Kind kind = Kind::view_angle;
    double value = 0;
    std::string name() const; // "view 22.5", "floor x0.5"
};
std::span<const SceneVariant> scene_variants();
// Applies a variant; throws PaperError when the scene has no polygon to scale.
rt::Scene apply_variant(rt::Scene scene, const SceneVariant& v);

// Runs the native renderer for each scene x grid (the SPD scene, then each variant of it) and loads our model V cycles from cells_dir (nesshi paper's cells at `size`).
struct GapsOptions {
    std::string cells_dir;
    std::vector<std::string> scenes{"balls", "mount", "rings", "tetra", "tree"};
    std::vector<int> grids{20, 50, 100};
    int size = 512;
    int threads = 0;                                  // native renderer threads (0: all cores)
    std::function<void(const std::string&)> progress; // a line per render, for stderr
};
std::vector<GapRow> run_gaps(const GapsOptions& o);

} // namespace nesshi::paper
