// `nesshi sweep`: a design-space sweep. A spec (TOML) names axes, each a value or a list; the cells
// are the product of the lists, each one machine run, stored with its provenance like the
// paper's cells (a resumed sweep loads the cells that are still the current run's) and reported
// as a tidy results.csv / results.jsonl (one row per cell: every axis, then every metric) and an
// SVG chart of one metric against one axis, one series per value of the other swept axes.
//
//   # sweep.toml
//   metrics = ["cycles.total", "cycles.os.processing"]   # dotted paths into the stats JSON
//   [axes]
//   scene = ["balls:1", "tetra:1"]
//   size = 32
//   grid = 10
//   fifo_capacity = [24, 48, 96]
//   cache_size = [4096, 65536]
//   [chart]
//   x = "fifo_capacity"
//   y = "cycles.total"
//
//   paper::SweepSpec spec = paper::load_sweep_spec("sweep.toml");
//   paper::SweepOptions o;  o.out_dir = "out";
//   paper::SweepRun r = paper::run_sweep(spec, o);
#pragma once

#include "paper/cell_engine.hpp"
#include "paper/paper.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace nesshi::paper {

// An axis and its values, as written (numbers and booleans in their TOML spelling).
struct SweepAxis {
    std::string name;
    std::vector<std::string> values;
};

struct SweepSpec {
    std::string file;              // where it came from, for messages
    std::vector<SweepAxis> axes;   // in the file's order
    std::vector<std::string> metrics;
    std::string chart_x, chart_y;  // "" = none asked: x = the first swept numeric axis, y = cycles.total
    bool chart_log_y = false;      // y_scale = "log": a log y axis (series far apart in size stay readable)
    bool chart_scale_given = false; // y_scale written; else the chart goes log when values span 30x or more
    // The machine axes' values (os_machine, ic_machine, seq_machine), each loaded once as the spec
    // is read: every cell takes its machine from here.
    std::map<std::string, kbuild::StageMachine> machines;
};

// The axes a spec may name (scene, size, grid, model, pes, balance, epoch, window, ray_slots,
// fifo_capacity, fifo_latency, quantum, cache, cache_size, cache_ways, cache_line, miss_cycles,
// resident, os_machine, ic_machine, seq_machine, kernels, max_cycles), with a line of help each.
const std::vector<std::pair<std::string, std::string>>& sweep_axis_names();
// Axes whose value 0 means "no limit" (fifo_capacity): a chart puts it last, as "unbounded".
bool sweep_axis_zero_unbounded(std::string_view axis);
// The metrics when a spec names none.
const std::vector<std::string>& default_sweep_metrics();

// Parses and checks a spec: unknown keys and axes, values of the wrong type, an empty list, a
// chart axis that is not an axis, each as a located error (file:line:col). Every value is checked
// by building each cell's options, so a bad value is reported before anything runs.
// A metric path that no stats JSON has (a typo, an empty component) is a located error too.
SweepSpec parse_sweep_spec(const std::string& text, const std::string& file);
SweepSpec load_sweep_spec(const std::string& file);

// How many cells the axes' product holds (saturating), and the product as text ("size 30 x grid 30").
std::size_t sweep_cell_count(const SweepSpec& s);
std::string sweep_product(const SweepSpec& s);
// A sweep of more cells is refused unless SweepOptions::max_cells allows it.
inline constexpr std::size_t kSweepMaxCells = 10'000;
// A cell's cycle limit per PE when no max_cycles axis names one: far above any scene's need (the
// paper's largest cells take about 420,000 per pixel), so only a kernel that never ends meets it.
inline constexpr std::uint64_t kSweepCyclesPerPixel = 2'000'000;

// One cell: a value per axis, in the spec's axis order.
struct SweepCell {
    std::vector<std::string> values;
    std::string id; // file-name-safe and stable: a hash of the axis names and values
};
std::vector<SweepCell> sweep_cells(const SweepSpec& s);

// The run a cell stands for.
struct SweepRunInputs {
    std::string scene = "balls";
    int grid = 0; // 0: the cost model's choice
    rt::RenderOptions render;
    machine::Options machine;
};
SweepRunInputs sweep_inputs(const SweepSpec& s, const SweepCell& c); // throws PaperError on a bad value

// The engine's progress, plus the axes of the cell just finished ("" otherwise).
struct SweepProgress : CellEngineProgress {
    std::string finished_cell;
};

// threads and shards as the cell engine's: batch schedulers without MPI run one shard per job;
// merging the jobs' cells/ folders and running the sweep once more writes the whole results
// without running anything.
struct SweepOptions : CellSpread {
    std::string out_dir = "sweep-out";
    std::size_t max_cells = kSweepMaxCells;
    std::uint64_t max_cycles = 0; // per PE, for cells with no max_cycles axis; 0: kSweepCyclesPerPixel x pixels
    std::function<void(const SweepProgress&)> progress;
};

struct SweepRun {
    std::vector<std::string> rows_jsonl;  // one per cell that has a result, in sweep_cells order
    std::vector<std::string> files;       // written into out_dir
    std::vector<std::string> failures;    // "cell axes: message"
    std::size_t loaded = 0, run = 0;
    // Cells with a result, of how many: a shard's run has only its own (and those stored), and
    // writes no results until the merged cells/ folder holds every cell.
    std::size_t with_result = 0, cells = 0;
    bool partial() const { return with_result < cells; }
};
// Runs (or loads) every cell, then writes results.csv, results.jsonl and chart.svg (a shard that
// does not complete the sweep writes its cells only). Throws PaperError naming failed cells after
// writing the rest.
SweepRun run_sweep(const SweepSpec& s, const SweepOptions& o);

// The outputs, from cells' stats JSON texts (by sweep_cells index; "" = no result).
std::string sweep_csv(const SweepSpec& s, const std::vector<SweepCell>& cells, const std::vector<std::string>& json);
std::vector<std::string> sweep_jsonl(const SweepSpec& s, const std::vector<SweepCell>& cells,
                                     const std::vector<std::string>& json);
std::string sweep_chart_svg(const SweepSpec& s, const std::vector<SweepCell>& cells,
                            const std::vector<std::string>& json);

} // namespace nesshi::paper
