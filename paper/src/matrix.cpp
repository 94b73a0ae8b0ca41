// The paper's matrix as cells of the cell engine: a cell per scene x grid x model, named by its
// file, checked as a cell record, the longest (by the paper's own time) first.
#include "paper/paper.hpp"

#include "paper/cell_engine.hpp"
#include "paper/published.hpp"

#include <filesystem>

namespace nesshi::paper {

namespace fs = std::filesystem;

namespace {

// The paper's time for the cell, to start the longest cells first (0 when the paper has none).
double estimated_cycles(const CellKey& k) {
    const PublishedTimes* p = find_published_times(paper_scene(k.scene), k.grid);
    if (!p) return 0;
    return k.model == machine::Model::V ? p->v.value : p->m.value;
}

} // namespace

MatrixResult run_matrix(const PaperOptions& o, const CellRunner& runner, const CellProvenanceFn& provenance) {
    const std::vector<CellKey> keys = matrix_cells(o);
    std::vector<Cell> cells;
    for (const CellKey& k : keys) {
        const fs::path file = fs::path(o.out_dir) / "cells" / cell_file_name(k);
        Cell c;
        c.name = file.stem().string();
        c.file = file.string();
        c.provenance = provenance ? provenance(k) : machine::Provenance{};
        c.work = estimated_cycles(k);
        c.run = [&runner, k](const CellProgressFn& progress) { return runner(k, progress); };
        c.check = [k, f = c.file](const std::string& text) { parse_cell(k, text, f); };
        cells.push_back(std::move(c));
    }
    CellEngineOptions eo;
    static_cast<CellSpread&>(eo) = o;
    if (o.progress)
        eo.progress = [&](const CellEngineProgress& e) {
            PaperProgress p;
            static_cast<CellEngineProgress&>(p) = e;
            p.size = o.size;
            CellRecord finished;
            if (e.finished_text && !e.finished_text->empty()) {
                finished = parse_cell(keys[e.finished], *e.finished_text, cells[e.finished].file);
                finished.wall_seconds = e.seconds;
                p.record = &finished;
            }
            o.progress(p);
        };
    CellEngineResult e = run_cells(cells, eo);
    MatrixResult r;
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (!e.texts[i].empty()) r.cells.push_back(parse_cell(keys[i], e.texts[i], cells[i].file));
    r.failures = std::move(e.failures);
    r.stale = std::move(e.stale);
    r.loaded = e.loaded;
    r.run = e.run;
    return r;
}

} // namespace nesshi::paper
