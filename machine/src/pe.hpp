// One processing element: OS and IC processors (ISS instances running the kernels), the SC
// stage, the FIFOs between them, and the scheduler that advances their clocks.
//
// Scheduling (models M and V). Each processor keeps its own clock. FIFO actions follow the turn
// rule (turns.hpp), so their order, and every cycle, is the same whatever the host's
// interleaving: the scheduler repeatedly runs the stage with the earliest bound on its next FIFO
// action (pe.cpp) with its turn horizon, and up to `quantum` cycles past it (a performance
// setting only); a stage waiting on a FIFO is not run until it can act, and then waits (counted)
// until its word's ready cycle or its room. Everything is a function of the inputs: deterministic.
// Model S: the three stages share one clock; whichever stage has work runs to completion of
// that work while the others wait, so the PE's time is the sum of the stages' loads.
#pragma once
#include "iss/stats.hpp"

#include "fifo.hpp"
#include "sc_stage.hpp"

#include "kernels/image.hpp"
#include "iss/memory.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"
#include "machine/machine.hpp"

#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace nesshi::machine {

// Built once per render, shared read-only by every PE.
struct MachineSetup {
    std::shared_ptr<const iss::Program> os_prog, ic_prog;
    kbuild::KernelBuild os_build, ic_build;
    kernels::MemImage os_image;
    kernels::MemImage ic_resident;
    std::shared_ptr<iss::PagedMemory> global; // the IC global memory (ICGM), shared by all ICs
    OpPrices sc_prices;
};

// Samples of FIFO occupancy for --trace-json.
struct Sample {
    std::uint64_t cycle = 0;
    std::uint32_t fifo[4] = {0, 0, 0, 0};  // os_in, ic_in, sc_from_os, sc_from_ic
};

// A stretch [start, end) of one stage's own clock for --trace-json, with the cycles of each kind
// spent in it (wait + communication + processing = end - start): the stage's counters read
// after every scheduler step, gathered into stretches of at least `Pe::kActivityCycles` (doubled,
// by merging neighbours, whenever a stage holds 8000). The stretches of a stage tile its time
// from 0 to the PE's end, so their sums are the stage's cycles in the statistics.
struct Activity {
    std::uint64_t start = 0, end = 0;
    std::uint64_t wait = 0, communication = 0, processing = 0;
};

struct PeResult {
    StageCycles os, ic, sc;
    iss::Stats os_detail, ic_detail; // what `nesshi sim` reports, for the OS's and the IC's processor
    std::uint64_t end = 0; // the PE's finishing cycle
    rt::RayStats rays;
    std::array<rt::TraceCounters, rt::kRayKinds> traversal{};
    std::uint64_t bundles = 0, visits = 0, returns = 0, misses = 0, hits = 0;
    std::uint64_t cache_accesses = 0, cache_misses = 0, max_fifo = 0;
    std::vector<Sample> samples;
    std::array<std::vector<Activity>, 3> activity; // os, ic, sc (--trace-json only)
};

class Pe;

// One PE, run in steps. Interleaved DIS: construct with the PE's corners, run_until(kNever),
// finish(). Dynamic DIS: construct with none, then alternately give() corners and run_until()
// the next epoch boundary; several PEs can run on different threads between boundaries.
class PeRun {
  public:
    PeRun(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo,
          std::vector<std::uint32_t> corners, CornerSink sink);
    ~PeRun();
    PeRun(PeRun&&) noexcept;
    PeRun& operator=(PeRun&&) noexcept;
    // Runs until all corners given so far are finished, or every stage's next action is at or
    // past `until`. Adds finished corners to `corners_done`. Throws on deadlock or a fault.
    void run_until(std::uint64_t until, std::atomic<std::uint64_t>& corners_done);
    void give(std::uint32_t corner, std::uint64_t at); // DIS hands over a corner at cycle `at`
    std::size_t room(std::size_t target) const;        // corners it can take before holding `target`
    bool done() const;                                  // every corner given is finished
    PeResult finish();                                  // clocks to the PE's end; the statistics

  private:
    std::unique_ptr<Pe> pe_;
};

// DIS (dis.cpp): simulate the PEs with corners distributed interleaved or dynamically (see
// Options); `threads` gets the host threads used.
std::vector<PeResult> run_interleaved(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt,
                                      const Options& mo, std::size_t ncorners, CornerSink sink, int& threads);
std::vector<PeResult> run_dynamic(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt,
                                  const Options& mo, std::size_t ncorners, CornerSink sink, int& threads);

// Chrome/Perfetto trace-event JSON: per PE a process (pid) with one thread per stage (OS, IC, SC)
// holding "X" slices named processing, communication and wait (from the Activity stretches; within
// a stretch drawn in that order), counter tracks of FIFO words, and of each stage's busy
// fraction (processing + communication over the sample interval, from the same slices).
void write_trace_json(const std::string& path, const std::vector<PeResult>& pes);
// The run as a picture (--timeline-svg): each stage's busy fraction (processing + communication)
// and each FIFO's words over time, from the same activity and samples (timeline_svg.cpp).
std::string timeline_svg(const std::vector<PeResult>& pes);

} // namespace nesshi::machine
