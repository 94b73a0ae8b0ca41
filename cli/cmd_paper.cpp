// `nesshi paper`: re-run the paper's evaluation (scenes x grids x models S, M, V) and write Tables
// 2-4, Fig. 6 and a summary. Cells are kept in OUT/cells, so an interrupted run resumes where it stopped.
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "lists.hpp"
#include "shards.hpp"
#include "stage_machines.hpp"
#include "outputs.hpp"
#include "ranges.hpp"

#include "base/progress.hpp"

#include "machine/kernel_report.hpp"
#include "paper/cluster.hpp"
#include "paper/paper.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <tuple>
#include <unistd.h>

namespace nesshi::cli {

namespace {


struct PaperArgs {
    int size = 512;
    std::string scenes = "balls,mount,rings,tetra,tree";
    std::string grids = "20,50,100";
    std::string models = "S,M,V";
    std::string out = "paper-out";
    int threads = 0;
    std::string shard; // "I/N"
    bool keep_other_builds = false;
    bool quiet = false;
    machine::Options machine; // the stages' machines and kernels
    StageMachineNames machine_names; // loaded into `machine` when the command runs
};

std::vector<machine::Model> parse_models(const std::string& s) {
    std::vector<machine::Model> models;
    for (const std::string& part : split_list(s)) {
        machine::Model m{};
        if (!machine::parse_model(part, m))
            throw UsageError(fmt::format("unknown model '{}' (available: S, M, V)", part));
        models.push_back(m);
    }
    return models;
}

// Prints a line per finished cell to stderr (progress, never stdout: `nesshi paper | head -2` gets the
// summary); on a terminal also a bar with the time left, redrawn in place.
class ProgressPrinter {
  public:
    ProgressPrinter(const paper::PaperOptions& o, bool tty)
        : out_(o.out_dir), shard_note_(o.shards > 1 ? fmt::format(" (shard {}/{})", o.shard, o.shards) : ""), tty_(tty) {}

    void operator()(const paper::PaperProgress& p) {
        if (p.size != size_) { // a new phase: the matrix, then the grid pre-pass
            size_ = p.size;
            clear_status();
            status("{}: {} cells at {}x{}: {} loaded from {}/cells, {} to run{}, {}\n",
                       phases_++ ? "grid pre-pass" : "paper", p.cells_total, size_, size_, p.cells_loaded, out_,
                       p.cells_to_run, shard_note_, at_a_time(p.threads, p.processes));
        }
        if (p.stale && (!p.stale->empty() || p.cells_other_build > 0)) {
            clear_status();
            report_stored(*p.stale, p.cells_other_build);
        }
        if (p.record) {
            clear_status();
            const paper::CellRecord& c = *p.record;
            status("  {:<10} g{:<4} {}  {:>12} Mcycles  {:>8.1f} s   [{}/{}{}]\n", c.key.scene, c.key.grid,
                       machine::model_name(c.key.model), paper::format_mcycles(static_cast<double>(c.total)),
                       c.wall_seconds, p.cells_run + p.cells_failed, p.cells_to_run, tty_ ? "" : "; " + timing(p));
        }
        if (tty_ && p.cells_to_run > 0) draw_status(p);
            }

    void clear_status() {
        if (status_shown_) status("\r\033[K");
        status_shown_ = false;
    }

  private:
    static std::string timing(const paper::PaperProgress& p) {
        std::string t = fmt::format("{} elapsed", base::format_duration(p.elapsed_seconds));
        if (p.fraction > 0.01 && p.fraction < 1)
            t += fmt::format(", ~{} left", base::format_duration(p.elapsed_seconds / p.fraction * (1 - p.fraction)));
        return t;
    }

    void draw_status(const paper::PaperProgress& p) {
        const int pct = static_cast<int>(p.fraction * 100);
        status("\r\033[K{} {:3}%  {}/{} cells  {}", base::progress_bar(pct, 30), pct, p.cells_run + p.cells_failed,
                   p.cells_to_run, timing(p));
        status_shown_ = true;
    }

    std::string out_, shard_note_;
    int size_ = 0, phases_ = 0;
    bool tty_, status_shown_ = false;
};

void run_paper_command(const PaperArgs& a) {
    paper::PaperOptions o;
    o.size = a.size;
    o.scenes = split_list(a.scenes);
    o.grids = parse_grids(a.grids);
    o.models = parse_models(a.models);
    refuse_stdout("--out", a.out, "it is a folder (the cells, tables and charts)");
    o.out_dir = a.out;
    o.threads = a.threads;
    if (!a.shard.empty()) std::tie(o.shard, o.shards) = parse_shard(a.shard);
    o.keep_other_builds = a.keep_other_builds;
    o.machine = a.machine;
    a.machine_names.load(o.machine);
    try {
        paper::validate(o); // before any output
    } catch (const paper::PaperError& e) { // every check of validate is about the options
        throw UsageError(e.message());
    }
    if (!a.quiet && paper::cluster().reports()) // every cell runs these schedules
        status("{}", machine::schedules_used(o.machine, o.models));
    auto printer = std::make_shared<ProgressPrinter>(o, isatty(STDERR_FILENO) != 0);
    if (!a.quiet) o.progress = [printer](const paper::PaperProgress& p) { (*printer)(p); };
    try {
        paper::PaperRun r = paper::run_paper(o);
        printer->clear_status();
        if (!paper::cluster().reports() || a.quiet) return; // under mpirun, rank 0 reports
        fmt::print("cells: {} loaded, {} run\n", r.loaded, r.run);
        if (r.files.empty()) // a shard that did not complete the matrix
            fmt::print("shard {}: the reports wait for every cell: merge the shards' {}/cells folders and run "
                       "`nesshi paper` once more\n", a.shard, a.out);
        else
            fmt::print("wrote {}/: {}\n", a.out, fmt::join(r.files, " "));
    } catch (...) {
        printer->clear_status();
        throw;
    }
}

} // namespace

void add_paper(CLI::App& app) {
    auto* cmd = app.add_subcommand("paper", "Re-run the paper's evaluation: Tables 2-4, Fig. 6 and a summary");
    auto a = std::make_shared<PaperArgs>();
    cmd->add_option("--size", a->size, "image size N x N (default 512, the paper's)")->check(between(1, 16384));
    cmd->add_option("--scenes", a->scenes,
                    "scenes, comma-separated (default balls,mount,rings,tetra,tree; NAME:SIZE or NFF)");
    cmd->add_option("--grids", a->grids, "voxels per side, comma-separated (default 20,50,100)");
    cmd->add_option("--models", a->models, "models, comma-separated (default S,M,V; S comes from the M run)");
    cmd->add_option("--out", a->out, "output folder (default paper-out); cells kept in OUT/cells");
    cmd->add_option("--threads", a->threads, "cells run at once (default: all cores)")->check(between(0, 1024));
    cmd->add_option("--shard", a->shard, kShardHelp);
    cmd->add_flag("--keep-other-builds", a->keep_other_builds, kKeepOtherBuildsHelp);
    cmd->add_option("--kernels", a->machine.kernels_dir, "kernel source folder (default: built in)");
    add_stage_machine_options(cmd, a->machine_names);
    cmd->add_flag("-q,--quiet", a->quiet, "no progress, no report");
    add_paper_gaps(*cmd);
    add_paper_versus(*cmd);
    cmd->require_subcommand(0, 1);
    cmd->callback([a, cmd] {
        if (!cmd->get_subcommands().empty()) return; // `nesshi paper gaps` ran its own callback
        run_paper_command(*a);
    });
}

} // namespace nesshi::cli
