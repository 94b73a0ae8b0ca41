// `nesshi paper`: the paper's evaluation re-run (Tables 2, 3, 4 and Fig. 6 of Gwun et al. 1993) as a resumable
// matrix of machine runs, one cell per scene x grid x model, and the reports built from it.
//
//   paper::PaperOptions po;  po.size = 64;  po.out_dir = "paper-out";
//   paper::PaperRun r = paper::run_paper(po); // runs or loads every cell; writes tables, chart, summary
//
// Model S is not simulated separately: a model-M run also gives S's time (machine::Stats::s_cycles: one
// processor executing the same instruction streams takes the sum of the stages' loads), as the issue
// specifies; that S equals a separate model-S run is tested with the machine. So each scene x grid costs
// one M run and one V run, and asking for S alone still runs M.
//
// Everything but simulate_cell() and run_paper() works on cell records, so the tables, chart and resumable
// runner are testable with synthetic cells and a stand-in CellRunner.
#pragma once

#include "base/error.hpp"
#include "machine/machine.hpp"
#include "machine/provenance.hpp"
#include "paper/cell_engine.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace nesshi::paper {

// Bad options, a malformed cell file ("FILE: error: ..."), failed cells.
class PaperError : public base::Error {
  public:
    using base::Error::Error;
};

// One cell of the matrix; its file is out_dir/cells/<cell_file_name>.
struct CellKey {
    std::string scene; // as given: built-in name ("balls", "tetra:1") or NFF path
    int grid = 0;
    machine::Model model = machine::Model::V; // M or V: S comes from M
    int size = 512;                       // image width = height
    bool operator==(const CellKey&) const = default;
};
std::string cell_file_name(const CellKey& k); // "balls-g20-V-512.json", "tetra_1-g4-M-8.json"

// The numbers the reports need from a cell's machine::stats_json ("cycles" object).
struct CellRecord {
    CellKey key;
    std::uint64_t total = 0;
    std::uint64_t s_cycles = 0; // model M only: model S's time
    machine::StageCycles os, ic, sc;
    double wall_seconds = 0; // host time of the simulation (0 if the file does not say)
};
// Parses a cell file's text; throws PaperError "FILE: error: ..." when a key is missing or wrong.
CellRecord parse_cell(const CellKey& key, const std::string& json_text, const std::string& file);
// A cell file also keeps the provenance of its run ("provenance") and a digest of its results
// ("digest", machine::result_digest). Stamps both onto a runner's stats JSON text.
std::string stamp_cell(const std::string& json_text, const machine::Provenance& p);
// Whether a stored cell is still the current run's: its differences from `expected` (empty when it
// is; "no provenance recorded" for a file written before nesshi kept it). Throws PaperError naming
// the file when its results do not match its digest (edited by hand) or it is not JSON. With
// `other_build` non-null, a cell of another build (machine::build_identity) is kept and
// *other_build says whether it is one; with nullptr, another build is a difference.
std::vector<std::string> stale_reasons(const std::string& json_text, const machine::Provenance& expected,
                                       const std::string& file, bool* other_build = nullptr);

// The engine's progress, plus the record of the cell just finished (nullptr: the start, a failure
// or a periodic update) and the image size of the phase (the grid pre-pass follows the matrix, smaller).
struct PaperProgress : CellEngineProgress {
    const CellRecord* record = nullptr;
    int size = 0;
};

// threads: cells run at once (one host thread per cell, each a 1-PE run; 0 = all cores); a shard
// runs its share of each phase's cells, and the reports are written only when every cell is there.
struct PaperOptions : CellSpread {
    int size = 512;
    std::vector<std::string> scenes = {"balls", "mount", "rings", "tetra", "tree"};
    std::vector<int> grids = {20, 50, 100};
    std::vector<machine::Model> models = {machine::Model::S, machine::Model::M, machine::Model::V};
    std::string out_dir = "paper-out";
    // What every cell runs on: the stages' machine descriptions (os_machine, ic_machine,
    // seq_machine) and kernels_dir; a cell sets the model, one PE and one host thread itself.
    machine::Options machine;
    // Called from one thread at a time: at the start, after each cell, and a few times a second.
    std::function<void(const PaperProgress&)> progress;
};
// Throws PaperError: unknown scene, grid < 1 or > 512, size < 1 or > 16384, no model.
void validate(const PaperOptions& o);
bool wants(const PaperOptions& o, machine::Model m);
// The cells to have: per scene x grid, V if V is asked for, M if S or M is.
std::vector<CellKey> matrix_cells(const PaperOptions& o);

// Runs one cell and returns its stats JSON text; `progress` (may be empty) gets (done, total).
using CellRunner = std::function<std::string(const CellKey&, const CellProgressFn&)>;
// What a cell's result depends on (stored with it, compared when it is loaded again).
using CellProvenanceFn = std::function<machine::Provenance(const CellKey&)>;
// The real runner: prepare + machine::render with 1 PE on 1 host thread, SPD mode, on `base`'s
// machines and kernels; and the provenance of that run.
std::string simulate_cell(const CellKey& k, const machine::Options& base, const CellProgressFn& progress);
machine::Provenance cell_provenance(const CellKey& k, const machine::Options& base);

struct MatrixResult {
    std::vector<CellRecord> cells;     // loaded and run, in matrix_cells order
    std::vector<std::string> failures; // "cell: message" for cells whose run threw
    std::vector<std::string> stale;    // "cell: what changed" for stored cells run again
    std::size_t loaded = 0, run = 0;
};
// Loads the cells whose files exist and are the current run's (by `provenance`; empty: every cell's
// is empty), runs the others, o.threads at a time, longest first, and stores each with its
// provenance and digest. A malformed or hand-edited cell file is an error naming it (delete it to
// re-run); a failing cell does not stop the others.
MatrixResult run_matrix(const PaperOptions& o, const CellRunner& run, const CellProvenanceFn& provenance = {});

// What the reports read.
struct PaperData {
    int size = 512;
    std::vector<std::string> scenes;
    std::vector<int> grids; // ascending
    std::vector<machine::Model> models;
    std::vector<CellRecord> cells;
    // Automatic grid choices, among `grids` (absent: not computed). auto_grid: the cost model of
    // rt::choose_grid_resolution (a native 64x64 pre-pass). prepass_grid: the paper's suggestion,
    // a low-resolution pre-pass on the machine: model V at prepass_size^2 pixels at each grid.
    std::map<std::string, int> auto_grid;
    std::map<std::string, int> prepass_grid;
    int prepass_size = 0;
    const CellRecord* find(const std::string& scene, int grid, machine::Model m) const;
};
PaperData make_data(const PaperOptions& o, std::vector<CellRecord> cells);

// Derived numbers, shared by the tables, chart and summary.
double scale_to_paper(int size);                    // (512 / size)^2
std::string paper_scene(const std::string& scene);  // "balls", "balls:4" -> "balls"; other -> ""
bool is_paper_scene_size(const std::string& scene); // built-in at the paper's size factor
std::array<int, 3> load_ratio(const CellRecord& v); // OS:IC:SC loads over the smallest, rounded
std::uint64_t s_time(const CellRecord& m);          // s_cycles, else the sum of the stage loads
int best_grid(const PaperData& d, const std::string& scene, machine::Model m); // 0 if no cell
machine::Model time_model(const PaperData& d); // the model best grids are judged by: V, M, S

// A report table: rendered as Markdown and as CSV from the same cells.
struct Table {
    std::string title;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> notes; // Markdown only, below the table
    // The CSV, when it differs from the Markdown: one fixed header whatever the size, plain
    // numbers in numeric columns (cycles as integers), an empty field where a value is missing,
    // flags and range ends in columns of their own.
    std::vector<std::string> csv_header;
    std::vector<std::vector<std::string>> csv_rows;
};
std::string to_markdown(const Table& t);
std::string to_csv(const Table& t);
std::string format_mcycles(double cycles); // millions, 4 significant digits, never an exponent

Table table2(const PaperData& d); // model V per stage, load ratio, beside the paper's
Table table3(const PaperData& d); // S, M, V and speed-ups, beside the paper's
Table table4(const PaperData& d); // VLIW speed-ups M/V, ILP and utilisation, beside the paper's ranges
std::string fig6_svg(const PaperData& d);
std::string summary_markdown(const PaperData& d);
// table2.md/.csv, table3.md/.csv, table4.md/.csv, fig6.svg, summary.md; returns the file names.
std::vector<std::string> write_reports(const PaperData& d, const std::string& out_dir);

struct PaperRun {
    PaperData data;
    std::vector<std::string> files;  // written into out_dir
    std::size_t loaded = 0, run = 0; // cells
};
// The pre-pass image size: 100 x 100 for the paper's 512 x 512 (about 4% of the pixels).
int prepass_size(int size);
// validate, run_matrix with simulate_cell, the pre-pass (its cells kept like the others), the
// automatic grid choices, write_reports. Throws PaperError
// naming the failed cells after writing the reports of the others.
PaperRun run_paper(const PaperOptions& o);

} // namespace nesshi::paper
