// Running a sweep: each cell one machine run, stored with its provenance, loaded again when a
// resumed sweep asks for the same run; cells run concurrently, the largest images first.
#include "paper/sweep.hpp"

#include "base/write_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <limits>

namespace nesshi::paper {

namespace fs = std::filesystem;

namespace {

std::string describe(const SweepSpec& s, const SweepCell& c) {
    std::vector<std::string> parts;
    for (std::size_t i = 0; i < s.axes.size(); ++i)
        if (s.axes[i].values.size() > 1) parts.push_back(fmt::format("{}={}", s.axes[i].name, c.values[i]));
    return parts.empty() ? std::string("the cell") : fmt::format("{}", fmt::join(parts, " "));
}

machine::Provenance provenance_of(const SweepRunInputs& in) {
    return machine::provenance(in.scene, in.grid, in.render, in.machine);
}

std::string simulate(const SweepRunInputs& in) {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene(in.scene), in.grid);
    const machine::Result r = machine::render(prep, in.render, in.machine);
    return rt::stats_text(machine::stats_json(prep, in.render, in.machine, r));
}

} // namespace

SweepRun run_sweep(const SweepSpec& s, const SweepOptions& o) {
    if (const std::size_t n = sweep_cell_count(s); n > o.max_cells)
        throw PaperError(base::SourceLoc(s.file),
                         fmt::format("{} cells ({}): more than {} (allow them with --max-cells {}, or sweep fewer values)",
                                     n == std::numeric_limits<std::size_t>::max() ? std::string("too many") : fmt::format("{}", n),
                                     sweep_product(s), o.max_cells, n));
    const bool limit_axis = std::any_of(s.axes.begin(), s.axes.end(), [](const SweepAxis& a) { return a.name == "max_cycles"; });
    const std::vector<SweepCell> cells = sweep_cells(s);
    std::vector<Cell> jobs;
    for (const SweepCell& c : cells) {
        Cell job;
        SweepRunInputs in = sweep_inputs(s, c);
        if (o.max_cycles && !limit_axis) in.machine.max_cycles = o.max_cycles;
        job.name = describe(s, c);
        job.file = (fs::path(o.out_dir) / "cells" / (c.id + ".json")).string();
        job.provenance = provenance_of(in);
        // Largest images and most PEs first, so the cell still running at the end is a short one.
        job.work = static_cast<double>(in.render.width) * in.render.height * in.machine.pes;
        job.run = [in](const CellProgressFn&) { return simulate(in); };
        jobs.push_back(std::move(job));
    }
    CellEngineOptions eo;
    static_cast<CellSpread&>(eo) = o;
    if (o.progress)
        eo.progress = [&](const CellEngineProgress& e) {
            if (!e.stale && e.finished >= cells.size()) return; // a line per finished cell
            SweepProgress p;
            static_cast<CellEngineProgress&>(p) = e;
            if (e.finished < cells.size()) p.finished_cell = jobs[e.finished].name;
            o.progress(p);
        };
    CellEngineResult e = run_cells(jobs, eo);
    SweepRun r;
    r.loaded = e.loaded;
    r.run = e.run;
    r.failures = std::move(e.failures);
    if (e.worker) return r; // rank 0 of the MPI run has the cells and writes the outputs
    const std::vector<std::string>& json = e.texts;
    r.cells = cells.size();
    r.with_result = static_cast<std::size_t>(std::count_if(json.begin(), json.end(), [](const std::string& t) { return !t.empty(); }));
    // A shard writes its cells only, until the merged cells/ folders hold the whole sweep.
    if (o.shards > 1 && r.partial() && r.failures.empty()) return r;

    const std::string csv = sweep_csv(s, cells, json);
    r.rows_jsonl = sweep_jsonl(s, cells, json);
    std::string jsonl;
    for (const std::string& row : r.rows_jsonl) jsonl += row + "\n";
    base::replace_file((fs::path(o.out_dir) / "results.csv").string(), csv);
    base::replace_file((fs::path(o.out_dir) / "results.jsonl").string(), jsonl);
    r.files = {"results.csv", "results.jsonl"};
    if (const std::string svg = sweep_chart_svg(s, cells, json); !svg.empty()) {
        base::replace_file((fs::path(o.out_dir) / "chart.svg").string(), svg);
        r.files.push_back("chart.svg");
    }
    if (!r.failures.empty())
        throw PaperError(fmt::format("{} of {} cell(s) failed (the results hold the others):\n  {}", r.failures.size(),
                                     cells.size(), fmt::join(r.failures, "\n  ")));
    return r;
}

} // namespace nesshi::paper
