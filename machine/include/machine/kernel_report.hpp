// The kernel cycle report (`nesshi kernels`): the kernels of kernels/, as built for each machine, measured on
// the ISS beside the paper's step counts, with their lower bounds.
//
// Each kernel runs on synthetic inputs built with the ABI's image builders (the workloads);
// figures come from the ISS's per-label region counters: the cycles and ops of a metric's label
// regions over how often it happened (region entries, loop steps, rays). ResMII and RecMII
// (sched/bounds.hpp) are computed from the machine description and the ops of the measured
// regions, or of one path through them, per loop iteration. What each metric measures, the
// paper's figures and the goals are data (kernel_metrics, kPaper, kernel_goals).
//
//   const machine::KernelReport r = machine::kernel_report(kernels::embedded());
//   fmt::print("{}", r.text());                      // the table, the goals, the legend
//   std::ofstream("k.json") << r.json() << "\n";     // {"kernels": [{"metric": ..., ...}, ...]}
#pragma once

#include "kbuild/workloads.hpp"
#include "kernels/paper_figures.hpp"
#include "kernels/sources.hpp"
#include "machine/machine.hpp"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::machine {

using kernels::kPaper; // the paper's step costs (kernels/paper_figures.hpp)
using kernels::PaperFigures;

// What a metric's cycles and ops are divided by.
enum class PerWhat {
    Entries,   // executions of the first bundle of each measured region
    EntriesOf, // executions of the first bundles of `count_labels`' regions
    Loads,     // executions of the measured bundles that load the occupancy byte (lbu): voxel steps
    Rays,      // the rays of the workload; the whole kernel's processing cycles, ILP and utilisation
};

// Where the bounds come from (they are per loop iteration: over the ops, / `iterations`).
enum class BoundsFrom {
    None,
    Regions, // every op of the measured regions
    Path,    // the fall-through path from label `path` through the first bundle that branches back to it
    Loops,   // that path from each of `labels` the program has (a loop's body, not its exit code)
};

struct KernelMetric {
    std::string metric;  // "dda_step"
    std::string machine; // "os", "ic", "seq"; the kernel is kernels::kernel_path of it
    kbuild::Workload workload = kbuild::Workload::EmptyGrid;
    std::vector<std::string> labels; // the label regions measured
    PerWhat per = PerWhat::Entries;
    std::vector<std::string> count_labels; // PerWhat::EntriesOf
    std::optional<double> paper;           // the paper's figure, when it has one
    double iterations = 1;                 // loop iterations in one pass over the bounded ops
    // Instead of `iterations`: as many as the bounded ops hold occupancy loads (lbu), one a voxel step.
    bool iterations_are_loads = false;
    BoundsFrom bounds = BoundsFrom::None;
    std::string path; // BoundsFrom::Path
    // A kernel of per-kind loops (ic/intersect.loops.pk) that defines `<run>_run`: the row is that
    // run's code (from its label to the next run's), per primitive of the workload, bounded by its
    // loop's kernel over as many iterations as it loads shape indices (REC_INDEX).
    std::string run;
    std::string note;
};
// The rows of the report, in its order.
const std::vector<KernelMetric>& kernel_metrics();

// A goal on one quantity of a metric on some machines: cycles at most `limit`, ILP at least.
struct KernelGoal {
    std::string what; // "voxel step on os", "ILP"
    std::string metric;
    std::vector<std::string> machines;
    bool ilp = false; // false: cycles <= limit; true: ILP >= limit
    double limit = 0;
};
const std::vector<KernelGoal>& kernel_goals();

struct KernelRow {
    std::string metric, machine;
    double cycles = 0;
    std::optional<double> paper;
    double ops = 0, ilp = 0, utilization = 0;
    double res_mii = 0, rec_mii = 0;   // 0: not computed
    double bound() const { return res_mii > rec_mii ? res_mii : rec_mii; } // a loop row's bound; 0 for the others
    // A row of software-pipelined runs of n iterations (the per-kind loops): ((n - 1) x bound() +
    // one iteration's longest path) / n, what fill and drain leave at the best; 0 for the others.
    double run_bound = 0;
    // What binds them (sched::ResBound/RecBound::binds, "..., / 2 iterations" when a pass holds
    // more); not printed in text() or json(), which keep their format.
    std::string res_binds, rec_binds;
    std::string note;
};

struct KernelReport {
    std::vector<KernelRow> rows;
    // The rows' machine column names the stage (os, ic, seq); a stage measured on another
    // description than its preset is listed here with that description's name.
    std::map<std::string, std::string> machines;
    // Per stage (os, ic, seq) whose kernel has loops scheduled for its machine: the pipeliner's
    // report of each (`nesshi pipeline`'s, from the kernel's .pk source).
    std::map<std::string, std::string> loop_reports;

    const KernelRow* find(std::string_view metric, std::string_view machine) const;
    // The table, the goals line (when every goal's rows are present), the legend.
    std::string text() const;
    // The loop reports, a heading per stage; a line saying so when no kernel has loops.
    std::string loops_text() const;
    // {"kernels": [...]}: each row's metric, machine, cycles, paper (or null), ops, ilp,
    // utilization, res_mii, rec_mii, bound, run_bound (or null), note; with `loops`, also
    // "loop_reports" (stage -> text); pretty-printed, no final newline.
    std::string json(bool loops = false) const;
};

// Runs every metric of kernel_metrics() on the kernels of `sources`. Throws std::runtime_error
// when a kernel does not assemble or does not behave (kbuild::KernelRunner).
// The machine each stage's rows are measured on. A description other than the preset gets the
// kernel's straight-line blocks scheduled for it (runner.hpp).
struct KernelMachines {
    kbuild::StageMachine os{"os"}, ic{"ic"}, seq{"seq"};
    const kbuild::StageMachine& of(std::string_view role) const;
};

KernelReport kernel_report(const kernels::SourceSet& sources, const KernelMachines& machines = {});

// What a run on `mo`'s machines will use, for stderr before it starts: per stage that runs on
// another description than its preset, the kernel file, how it was scheduled for the machine and
// its headline costs ("dda_step 15.05 (ResMII 5.00, RecMII 9.00)"); "" when every stage runs on its preset.
// One report serves several models (`paper` runs V and M).
std::string schedules_used(const Options& mo, const std::vector<Model>& models);
inline std::string schedules_used(const Options& mo) { return schedules_used(mo, {mo.model}); }

} // namespace nesshi::machine
