// The resumable cell engine under `nesshi paper` and `nesshi sweep`: a list of independent cells,
// each one machine run whose stats JSON is stored (stamped with its provenance) in its own file.
// Stored cells that are still the current run's are loaded; the others run, the most work first,
// on threads, on a shard of the list, or over the processes of `mpirun -n K` (rank 0 hands the
// cells out one at a time and writes every file; paper/cluster.hpp).
//
//   std::vector<paper::Cell> cells = ...;          // file, provenance, work, run
//   paper::CellEngineResult r = paper::run_cells(cells, options);
//   r.texts[i]                                      // cell i's stored JSON ("" when it has none)
#pragma once

#include "machine/provenance.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace nesshi::paper {

// A running cell's progress: (done, total) in any unit.
using CellProgressFn = std::function<void(std::uint64_t, std::uint64_t)>;

struct Cell {
    std::string name; // for messages: "balls-g20-V-512", "fifo_capacity=24 scene=balls"
    std::string file; // where it is stored
    machine::Provenance provenance;
    double work = 0; // expected cost, to run the longest first and weigh the progress (0: unknown)
    // The run: returns the stats JSON text (throws on failure). `progress` may be empty.
    std::function<std::string(const CellProgressFn& progress)> run;
    // Checks a current stored text or a new one before it is kept (throws on a malformed one); may be empty.
    std::function<void(const std::string& text)> check;
};

struct CellEngineProgress {
    std::size_t cells_total = 0, cells_loaded = 0, cells_to_run = 0, cells_run = 0, cells_failed = 0;
    std::size_t cells_other_build = 0; // of the loaded: another build's (keep_other_builds)
    double fraction = 0;        // of the cells to run, with the running ones' partial progress
    double elapsed_seconds = 0; // of this run
    int threads = 1;            // cells at once in this process
    int processes = 1;          // of an MPI run
    // At the start (else nullptr): "cell: what changed" for each stored cell run again.
    const std::vector<std::string>* stale = nullptr;
    // After a cell finished (else SIZE_MAX): its index, its stored text ("" if it failed), its host time.
    std::size_t finished = static_cast<std::size_t>(-1);
    const std::string* finished_text = nullptr;
    double seconds = 0;
};

// How a run spreads its cells (paper::PaperOptions and SweepOptions have the same).
struct CellSpread {
    int threads = 0; // cells at once per process (0: the cores, shared among one host's processes)
    // Run only shard `shard` of `shards` (1-based): the cells whose index is shard - 1 modulo
    // shards; the others are loaded when stored, else have no result.
    int shard = 1, shards = 1;
    // Keep stored cells that another build of nesshi computed (machine::build_identity), when
    // they differ in nothing else; they are counted (CellEngineResult::other_build). By default
    // they run again: a new build may time the machine differently.
    bool keep_other_builds = false;
};

struct CellEngineOptions : CellSpread {
    // From one thread at a time: at the start, after each cell, and a few times a second.
    std::function<void(const CellEngineProgress&)> progress;
};

struct CellEngineResult {
    std::vector<std::string> texts;    // by cell index: the stored JSON, "" for no result
    std::vector<std::string> failures; // "cell: message"
    std::vector<std::string> stale;    // "cell: what changed"
    std::size_t loaded = 0, run = 0;
    std::size_t other_build = 0; // of the loaded: computed by another build (keep_other_builds)
    // This process is an MPI worker: it ran cells for rank 0 and has no results (texts all "").
    bool worker = false;
};

// Loads, runs and stores every cell (each file written whole as soon as its cell finishes, so an
// interrupted run loses only the cells in flight). A stored file of another provenance runs again
// unread (an older nesshi may have written another layout); a current one that `check` refuses, or
// a file whose results do not match its digest, is an error naming it; a failing cell does not stop
// the others.
CellEngineResult run_cells(const std::vector<Cell>& cells, const CellEngineOptions& o);

} // namespace nesshi::paper
