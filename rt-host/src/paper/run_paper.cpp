// `nesshi paper` as one call: check the options, choose grids automatically (for the summary), run
// or load the matrix, write the reports.
#include "rt/paper.hpp"

#include <fmt/format.h>

namespace nesshi::rt::paper {

PaperRun run_paper(const PaperOptions& o) {
    validate(o);
    MatrixResult m = run_matrix(o, simulate_cell);
    PaperRun r{make_data(o, std::move(m.cells)), {}, m.loaded, m.run};
    for (const std::string& scene : o.scenes) {
        const PreparedScene prep = prepare(load_scene(scene), 1); // shapes only; the grid is chosen below
        r.data.auto_grid[scene] = choose_grid_resolution(prep.scene, prep.shapes).n;
    }
    r.files = write_reports(r.data, o.out_dir);
    if (!m.failures.empty())
        throw PaperError(fmt::format("{} cell(s) failed (the reports show the others):\n  {}", m.failures.size(),
                                     fmt::join(m.failures, "\n  ")));
    return r;
}

} // namespace nesshi::rt::paper
