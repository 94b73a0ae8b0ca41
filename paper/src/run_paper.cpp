// `nesshi paper` as one call: check the options, run or load the matrix, the grid pre-pass and the
// automatic grid choices, write the reports.
#include "paper/cluster.hpp"
#include "paper/paper.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

namespace {

// The candidate of `grids` with the least cost; `cost` gives nullopt-like -1 for unknown grids.
template <class Cost>
int cheapest(const std::vector<int>& grids, Cost cost) {
    int best = 0;
    double best_cost = 0;
    for (int g : grids) { // ascending: a tie goes to the coarser grid
        const double c = cost(g);
        if (c >= 0 && (best == 0 || c < best_cost)) {
            best = g;
            best_cost = c;
        }
    }
    return best;
}

} // namespace

int prepass_size(int size) { return std::max(8, static_cast<int>(std::lround(size * 100.0 / 512.0))); }

PaperRun run_paper(const PaperOptions& o) {
    validate(o);
    const CellRunner run = [&o](const CellKey& k, const CellProgressFn& progress) {
        return simulate_cell(k, o.machine, progress);
    };
    const CellProvenanceFn provenance = [&o](const CellKey& k) { return cell_provenance(k, o.machine); };
    MatrixResult m = run_matrix(o, run, provenance);
    PaperRun r{make_data(o, m.cells), {}, m.loaded, m.run};

    // The paper's suggestion: time a low-resolution render at each grid, keep the fastest.
    PaperOptions pre = o;
    pre.size = prepass_size(o.size);
    pre.models = {machine::Model::V};
    MatrixResult p = run_matrix(pre, run, provenance);
    if (!cluster().reports()) return r; // rank 0 of the MPI run has the cells and writes the reports
    r.data.prepass_size = pre.size;
    for (const std::string& scene : o.scenes) {
        auto v_time = [&](int g) {
            for (const CellRecord& c : p.cells)
                if (c.key.scene == scene && c.key.grid == g) return static_cast<double>(c.total);
            return -1.0;
        };
        if (const int g = cheapest(r.data.grids, v_time)) r.data.prepass_grid[scene] = g;
        // The cost model's choice among the matrix's grids (its candidates are 20, 35, 50, 70, 100).
        const rt::PreparedScene prep = rt::prepare(rt::load_scene(scene), 1); // shapes only
        const rt::GridChoice choice = rt::choose_grid_resolution(prep.scene, prep.shapes);
        auto model_cost = [&](int g) {
            for (const auto& [n, c] : choice.costs)
                if (n == g) return c;
            return -1.0;
        };
        const int g = cheapest(r.data.grids, model_cost);
        r.data.auto_grid[scene] = g ? g : choice.n;
    }
    const std::size_t matrix_failures = m.failures.size(), prepass_failures = p.failures.size();
    m.failures.insert(m.failures.end(), p.failures.begin(), p.failures.end());
    // A shard writes its cells only, until the merged cells/ folders hold the whole matrix.
    const bool complete = m.cells.size() == matrix_cells(o).size() && p.cells.size() == matrix_cells(pre).size();
    if (o.shards == 1 || complete) r.files = write_reports(r.data, o.out_dir);
    if (!m.failures.empty())
        throw PaperError(fmt::format("{} cell(s) failed: {} of the matrix, {} of the grid pre-pass at {}x{} (the reports "
                                     "show the others):\n  {}",
                                     m.failures.size(), matrix_failures, prepass_failures, pre.size, pre.size,
                                     fmt::join(m.failures, "\n  ")));
    return r;
}

} // namespace nesshi::paper
