// `nesshi sweep SPEC.toml`: a design-space sweep (paper/sweep.hpp). Progress and status go to
// stderr; the results go to files in --out.
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "shards.hpp"

#include "base/progress.hpp"
#include "paper/cluster.hpp"
#include "paper/sweep.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <memory>
#include <tuple>

namespace nesshi::cli {

namespace {

struct SweepArgs {
    std::string spec, out = "sweep-out";
    int threads = 0;
    std::string shard; // "I/N"
    bool keep_other_builds = false;
    bool quiet = false;
    std::size_t max_cells = paper::kSweepMaxCells;
    std::uint64_t max_cycles = 0;
};

std::string axis_help() {
    std::string o = "Run a design-space sweep: the product of the spec's axes, one machine run per cell\n\n"
                    "SPEC (TOML): metrics = [\"cycles.total\", ...] (dotted paths into the stats JSON), [axes] with\n"
                    "NAME = value or [values], [chart] x = \"AXIS\", y = \"METRIC\", y_scale = \"log\" (default linear). Axes:\n";
    for (const auto& [name, help] : paper::sweep_axis_names()) o += fmt::format("  {:<14} {}\n", name, help);
    return o;
}

void run_sweep_command(const SweepArgs& a) {
    const paper::SweepSpec spec = paper::load_sweep_spec(a.spec);
    paper::SweepOptions o;
    o.out_dir = a.out;
    o.max_cells = a.max_cells;
    o.max_cycles = a.max_cycles;
    if (!a.quiet && paper::cluster().reports() && paper::sweep_cell_count(spec) <= a.max_cells)
        status("sweep: {} cells ({}); looking for stored ones in {}/cells\n", paper::sweep_cell_count(spec),
                   paper::sweep_product(spec), a.out);
    o.threads = a.threads;
    if (!a.shard.empty()) std::tie(o.shard, o.shards) = parse_shard(a.shard);
    o.keep_other_builds = a.keep_other_builds;
    if (!a.quiet)
        o.progress = [shard_note = a.shard.empty() ? std::string() : " (shard " + a.shard + ")"](const paper::SweepProgress& p) {
            if (p.stale) {
                status("sweep: {} cells: {} loaded, {} to run{}, {}\n", p.cells_total, p.cells_loaded,
                           p.cells_to_run, shard_note, at_a_time(p.threads, p.processes));
                report_stored(*p.stale, p.cells_other_build);
                return;
            }
            const std::size_t done = p.cells_run + p.cells_failed;
            std::string left;
            if (done > 0 && done < p.cells_to_run)
                left = fmt::format(", ~{} left", base::format_duration(p.elapsed_seconds / static_cast<double>(done) *
                                                                        static_cast<double>(p.cells_to_run - done)));
            status("  {:<40} {:>7.1f} s   [{}/{}; {} elapsed{}]\n", p.finished_cell, p.seconds, done, p.cells_to_run,
                       base::format_duration(p.elapsed_seconds), left);
        };
    const paper::SweepRun r = paper::run_sweep(spec, o);
    if (!paper::cluster().reports()) return; // rank 0 of the MPI run reports
    if (a.quiet) return;
    if (r.files.empty()) // a shard's part
        status("cells: {} loaded, {} run; {} of the sweep's {} cells in {}/cells (shard {}): no results until they all are "
               "(merge the shards' cells/ folders into one and run the sweep again without --shard: stored cells load)\n",
               r.loaded, r.run, r.with_result, r.cells, a.out, a.shard);
    else
        status("cells: {} loaded, {} run\nwrote {}/: {}\n", r.loaded, r.run, a.out, fmt::join(r.files, " "));
}

} // namespace

void add_sweep(CLI::App& app) {
    auto* cmd = app.add_subcommand("sweep", "Run a design-space sweep over machine, FIFO, cache and scene axes");
    cmd->description(axis_help());
    auto a = std::make_shared<SweepArgs>();
    cmd->add_option("spec", a->spec, "the sweep spec (TOML)")->required();
    cmd->add_option("--out", a->out, "output folder (default sweep-out): cells/, results.csv, results.jsonl, chart.svg");
    cmd->add_option("--threads", a->threads, "cells run at once (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--shard", a->shard, kShardHelp);
    cmd->add_flag("--keep-other-builds", a->keep_other_builds, kKeepOtherBuildsHelp);
    cmd->add_option("--max-cells", a->max_cells, fmt::format("refuse a spec of more cells than this (default {})", paper::kSweepMaxCells))
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-cycles", a->max_cycles, fmt::format("cycle limit per PE of a cell with no max_cycles axis; a cell "
                                                               "past it fails alone (default {} per pixel)", paper::kSweepCyclesPerPixel))
        ->check(CLI::PositiveNumber);
    cmd->add_flag("-q,--quiet", a->quiet, "no progress");
    cmd->callback([a] { run_sweep_command(*a); });
}

} // namespace nesshi::cli
