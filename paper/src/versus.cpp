// Two stored paper runs side by side.
#include "paper/versus.hpp"

#include "base/read_file.hpp"
#include "report_format.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <tuple>

namespace nesshi::paper {

PaperData load_paper_data(const PaperOptions& o) {
    std::vector<CellRecord> cells;
    for (const CellKey& k : matrix_cells(o)) {
        const std::string file = (std::filesystem::path(o.out_dir) / "cells" / cell_file_name(k)).string();
        if (!std::filesystem::exists(file))
            throw PaperError(base::SourceLoc(file), "no such cell (run `nesshi paper` with the same --size, --scenes "
                                                    "and --grids and this --out first)");
        cells.push_back(parse_cell(k, base::read_file(file), file));
    }
    return make_data(o, std::move(cells));
}

Table versus_table(const VersusRun& a, const VersusRun& b) {
    Table t;
    t.title = fmt::format("Table 3 of two runs: {} against {} (millions of cycles at {}x{})", a.name, b.name,
                          a.data.size, a.data.size);
    t.header = {"scene", "grid"};
    for (const VersusRun* r : {&a, &b})
        for (const char* c : {"M", "V", "M/V"}) t.header.push_back(fmt::format("{} {}", c, r->name));
    t.header.push_back(fmt::format("V {} / V {}", b.name, a.name));
    for (const char* stage : {"OS", "IC"})
        for (const VersusRun* r : {&a, &b}) t.header.push_back(fmt::format("{} ILP {}", stage, r->name));
    t.header.push_back("paper M/V");
    // The CSV is long: a row per scene, grid and run, named in its `run` column.
    t.csv_header = {"scene", "grid", "size", "run", "m_cycles", "v_cycles", "m_over_v", "os_ilp", "ic_ilp"};
    add_published_csv_header(t.csv_header, "paper_m_over_v");
    auto cell = [](const VersusRun& r, const std::string& scene, int g, machine::Model m) {
        const CellRecord* c = r.data.find(scene, g, m);
        if (!c)
            throw PaperError(fmt::format("{}: no model {} cell for {} at grid {}", r.name, machine::model_name(m), scene, g));
        return c;
    };
    for (const std::string& scene : a.data.scenes)
        for (int g : a.data.grids) {
            const CellRecord *am = cell(a, scene, g, machine::Model::M), *av = cell(a, scene, g, machine::Model::V);
            const CellRecord *bm = cell(b, scene, g, machine::Model::M), *bv = cell(b, scene, g, machine::Model::V);
            std::vector<std::string> row = {scene, std::to_string(g)};
            for (auto [m, v] : {std::pair{am, av}, std::pair{bm, bv}}) {
                row.push_back(format_mcycles(static_cast<double>(m->total)));
                row.push_back(format_mcycles(static_cast<double>(v->total)));
                row.push_back(format_quotient(static_cast<double>(m->total), static_cast<double>(v->total)));
            }
            row.push_back(format_quotient(static_cast<double>(bv->total), static_cast<double>(av->total)));
            for (double ilp : {av->os.ilp(), bv->os.ilp(), av->ic.ilp(), bv->ic.ilp()}) row.push_back(fmt::format("{:.2f}", ilp));
            const PublishedTimes* p = find_published_times(paper_scene(scene), g);
            row.push_back(p ? format_published(p->m_over_v) : kMissing);
            t.rows.push_back(std::move(row));
            for (auto [r, m, v] : {std::tuple{&a, am, av}, std::tuple{&b, bm, bv}}) {
                t.csv_rows.push_back({scene, std::to_string(g), std::to_string(a.data.size), r->name,
                                      std::to_string(m->total), std::to_string(v->total),
                                      csv_field(static_cast<double>(m->total) / static_cast<double>(v->total)),
                                      csv_field(v->os.ilp()), csv_field(v->ic.ilp())});
                add_published_csv(t.csv_rows.back(), p ? &p->m_over_v : nullptr);
            }
        }
    t.notes.push_back(kReconstructedNote);
    return t;
}

} // namespace nesshi::paper
