// Software pipelining from linear assembly: `nesshi pipeline FILE.sa`.
//
// A linear-assembly file is an ordinary source in which one region
//
//     .pipeline r9              # r9 holds the trip count (iterations) on entry; 0 after the loop
//     flw   %x, xs(r1)          # one operation per line, in sequential order
//     flw   %y, ys(r1)          # %name: a virtual register, defined once per iteration
//     fmul  %t, f0, %x
//     fadd  %s, %t, %y
//     fsw   %s, ys(r1)
//     addi  r1, r1, 4           # an induction register: stepped by a constant each iteration
//     .endpipeline
//
// holds one iteration. Everything outside the region passes through unchanged. The tool builds
// the dependence graph (registers with their latencies and the exposed-pipeline rules, memory,
// FIFO order, loop-carried distances), modulo-schedules it from the MII upward (iterative modulo
// scheduling after Rau; bundles checked with isa::check_bundle, so any machine description is
// scheduled exactly), adjusts the offsets of memory operations on induction registers across
// stages, expands virtual registers over free physical ones as their lifetimes require (the
// kernel unrolled by a power of two), and emits prologue, kernel and epilogue. Each kernel copy
// counts one iteration and leaves after the last, into the epilogue of its register rotation, so
// any trip count runs pipelined; counts too small for the pipeline run a sequential copy of the
// body, so every trip count >= 0 is correct.
//
// `.pipeline while` instead has no trip count and one exit test, a conditional branch to `exit`
// (`beqz %go, exit`); iterations start before earlier tests are decided, with no side effect
// (stores, FIFO words, physical registers but inductions, loads unless `.speculate rA` names
// their base, or `.speculate %p` for a base computed or loaded in the loop, as in a pointer
// chase) until those tests pass; each prologue pass and kernel copy has its own exit path.
// There `.carry %v, IN[, OUT[, OLD]]` carries %v between iterations (read before its write; in
// from IN, out to OUT, and to OLD the value the exiting iteration started with) and
// `.liveout %v, REG` hands the exiting iteration's %v out.
//
// `.noalias rA, rB` inside the region declares that accesses based on rA and on rB never overlap.
// `.trip MIN[, EXPECTED]` in a counted region: at least MIN iterations run (TripChoice).
// Not yet: virtual registers carried from one iteration to the next of a counted loop (use a
// physical register, as for an accumulator), branches inside the region other than a while loop's exit test.
//
// A file may hold several regions (not nested): each is pipelined in turn, in file order, with
// the later ones standing as their sequential meanings; the scratch registers of one are free for
// the next. Their labels are __sa_... for the first, __sa1_..., __sa2_... for the others.
//
//   sched::PipelineResult r = sched::pipeline_source(text, "loop.sa", isa::load_machine("os"), {});
//   fmt::print("{}", r.pipelined);          // assembles with `nesshi asm` with no diagnostic
//   fmt::print("{}", r.report);             // II, bounds, stages, unroll, registers, the MRT
#pragma once

#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::sched {

struct PipelineOptions {
    int ii = 0;              // 0: search upward from the MII; else this II only
    int max_ii_search = 64;  // how far above the MII to search
    // > 0: give up after this many IIs in a row at which no op order gave a modulo schedule at
    // all (not one whose code failed to assemble): a larger II rarely helps such a loop, and a
    // caller with another candidate (kbuild::assemble_kernel) need not pay the whole search.
    int max_unscheduled_iis = 0;
    // > 0: when the II found is above the MII, every modulo reservation table (a Gecode model) at
    // each II from the MII up, for this long in all; the first whose code assembles is kept. The
    // report says "II proven optimal" (every smaller II has no table) or "best found, bound not
    // proven" with the reason (time, or tables the assembler rejected).
    double exact_seconds = 0;
    // How the file's .include lines are read (embedded kernel sources); default the file system.
    std::function<bool(const std::string& path, std::string& text)> read_file;
    // A file with several regions: only this one (0-based) is pipelined, the others are written as
    // their sequential meanings (verification checks one region at a time). Default: every one.
    std::optional<int> region;
    // The solver's search for the shortest iteration at the II found (z3, a fixed budget of work:
    // up to about a second a region on this project's machine). Every run of the loop pays the iteration's length once, to fill and drain, so it
    // pays where runs are short. Auto: when the region's `.trip` says its runs are short enough
    // that the most it could gain is kShortenWorthPercent of a run or more (a loop without `.trip`,
    // and a while loop, is taken to run long: the II is what counts); Always: whenever the
    // iteration is half an II or more above its longest path (the kernel build: voxel lists are
    // short); Never.
    enum class Shorten { Auto, Always, Never };
    Shorten shorten = Shorten::Auto;
};

inline constexpr int kShortenWorthPercent = 10;

// `.trip MIN[, EXPECTED]` in a counted region: the schedule is the one whose whole run (prologue,
// kernel passes with their branch bubbles, epilogue; the sequential copy below the pipeline's minimum)
// takes the fewest cycles at EXPECTED trips (default MIN), among the schedules the search finds
// at each II from the first that works up to where EXPECTED x II alone exceeds the best; and the
// code omits what MIN makes dead (the zero-trip test, the short-trip path).
// A whole run's cycles by where they go: the kernel passes (with their bubbles), the fill and
// drain (counter set-up, prologue, entry nops, epilogue and drain), and the rest: the tests, the
// sequential copy's iterations (every one of a trip too short for the pipeline) and their branches.
struct RunParts {
    std::int64_t kernel = 0, fill_drain = 0, outside = 0;
    std::int64_t sequential_iterations = 0;
    std::int64_t total() const { return kernel + fill_drain + outside; }
};

struct TripChoice {
    int min = 0, expected = 0, line = 0; // line: of the .trip
    struct Option : RunParts {
        int ii = 0, stages = 0, unroll = 1;
        int groups = 1; // the kernel repeated, an exit test between repeats: unroll x groups copies
        std::int64_t cycles = 0; // whole run at `expected` trips, without memory stalls: total()
    };
    Option chosen;
    Option first;                 // the schedule the rule without .trip takes (the first found that assembles)
    int candidates = 0;           // schedules costed
    int ii_first = 0, ii_last = 0; // the IIs searched
    bool short_path = true;       // the chosen code still has the sequential path for short trips
    std::string text() const;     // report lines, "#   " each
    std::string json() const;     // one object
};

// One region's schedule, for whoever builds code with the tool (kbuild::KernelBuild).
struct LoopSummary {
    int line = 0; // of its .pipeline
    bool is_while = false;
    int ii = 0, mii = 0, res_mii = 0, rec_mii = 0, stages = 0, unroll = 1;
    // The least II not proven impossible: mii, or above it where every II from mii up has no
    // modulo schedule (the recurrences, or the constraint model's proof).
    int proven_mii = 0;
    int groups = 1;                 // the kernel repeated, an exit test between repeats (TripChoice::Option)
    std::optional<TripChoice> trip; // with `.trip`
    // One iteration from its first issue to its last landing, and its longest path (as in
    // PipelineResult): a run of N iterations takes at least (N - 1) x MII + the longest path.
    int iteration_cycles = 0, iteration_lower = 0;
    std::string json() const;       // one object; `trip` null without .trip
    // The schedule as a picture (`nesshi pipeline --svg`): the modulo reservation table, ops
    // coloured by iteration stage, with the register ports per row, above the virtual registers'
    // lifetimes (LoopReport::svg draws it).
    std::string svg;
};

struct PipelineResult {
    std::string linear;    // the region as a sequential loop (the reference meaning), whole file
    std::string pipelined; // the region software-pipelined, whole file: its `# machine:` line, report, code
    std::string report;    // the text block (also the pipelined file's header comment)
    std::string code;      // the pipelined file after its machine line and report
    // Where the region begins in `linear` and in `pipelined` (one region pipelined): verification
    // sets the trip count there. With several regions pipelined at once, not set.
    std::optional<std::size_t> linear_region_at, pipelined_region_at;
    int ii = 0, mii = 0, res_mii = 0, rec_mii = 0;
    int stages = 0, unroll = 1;
    int groups = 1; // a counted loop's kernel: unroll x groups copies, an exit test after each unroll
    // One iteration, from its first issue to its last landing, and the longest path through it
    // (no schedule is shorter): a run pays about the iteration to fill and drain.
    int iteration_cycles = 0, iteration_lower = 0;
    int min_pipelined_trip = 0;          // smaller trip counts run the sequential copy only
    int min_trip = 0;                    // `.trip MIN`: smaller counts are the user's error (0: none)
    // The file's .pipeline regions. With several and no PipelineOptions::region, the code and the
    // report (one block per region) cover them all; the fields above and below describe the first.
    int regions = 1;
    std::vector<LoopSummary> loops; // each region pipelined, in file order
    std::string trip_register;           // "r9"
    std::vector<std::string> scratch;    // physical registers the tool allocated (virtuals, counter)
    std::vector<std::string> source_registers; // registers the source names (live across the region)
    // `.pipeline while`: the exit test's stage; the register where the sequential meaning counts
    // the iterations that do not exit (not compared; verification reads it).
    bool is_while = false;
    int exit_stage = 0;
    std::string iteration_register;
};

// Throws std::runtime_error "FILE:LINE: error: ..." on malformed input, or when no schedule is
// found or the registers do not fit.
PipelineResult pipeline_source(std::string_view text, std::string_view filename, const isa::Machine& m,
                               const PipelineOptions& opts);

// The file with its region replaced by the region's sequential meaning between the comment lines
// kRegionBegin and kRegionEnd, assembled nowhere: legalizing the code around a region for a
// machine starts from it (kbuild::assemble_kernel), then restore_region puts the region back.
inline constexpr const char* kRegionBegin = "# sequential meaning of the .pipeline region: begin";
inline constexpr const char* kRegionEnd = "# sequential meaning of the .pipeline region: end";
std::string sequential_region(std::string_view text, std::string_view filename, const isa::Machine& m);
std::string restore_region(std::string_view legalized, std::string_view original);
// The 1-based line of each region's `.pipeline`, in file order (`#if machine` sections resolved
// for m, which keeps the line numbers).
std::vector<int> region_lines(std::string_view text, std::string_view filename, const isa::Machine& m);

// `r`'s sequential meaning and pipelined code (one region pipelined) with `li TRIP, n` and the
// nops of its latency just before the region: a counted loop run n times.
struct TripPrograms {
    std::string linear, pipelined;
};
TripPrograms with_trip(const PipelineResult& r, const isa::Machine& m, std::uint32_t n);

// Verification by simulation of the code `r` is (one region pipelined, the file's others
// sequential): for each trip count, both programs with `li TRIP, n` (and the nops of its latency)
// just before the region are assembled and handed to `run`, which runs them on random data and
// returns the first difference, or nothing when they agree. Returns the first failure as
// "trip N: ...". The code is not scheduled again: what is verified is what was written.
using DifferentialRun = std::function<std::optional<std::string>(const isa::ObjectFile& linear,
                                                                 const isa::ObjectFile& pipelined)>;
std::optional<std::string> verify(const PipelineResult& r, std::string_view filename, const isa::Machine& m,
                                  const std::vector<std::uint32_t>& trip_counts, const DifferentialRun& run);
// The trip counts that cover the sequential path, the shortest pipelined run and every kernel
// copy's exit: 0, 1, min - 1, min, min + 1, ..., min + K with
// K = max(2 x unroll + 1, unroll x (groups + 1)); with `.trip MIN`, those of at least MIN, and
// MIN, MIN + 1, ..., MIN + K.
std::vector<std::uint32_t> verification_trips(const PipelineResult& r);

// Verification of a while loop: the data decide where it exits, so each run draws new random data
// (`seed`) and reports, in `exits`, the iterations the sequential meaning completed before its
// exit (the value of PipelineResult::iteration_register).
using WhileRun = std::function<std::optional<std::string>(const isa::ObjectFile& linear, const isa::ObjectFile& pipelined,
                                                          std::uint64_t seed, std::uint32_t& exits)>;
struct WhileVerification {
    std::optional<std::string> failure;   // "seed N (exit after K iterations): ..."
    std::set<std::uint32_t> exits;        // the exit iterations the runs covered
    std::set<std::string> paths;          // the exit paths they took ("prologue pass 1", "kernel copy 0")
    int path_count = 0;                   // exit paths the code has
};
WhileVerification verify_while(const PipelineResult& r, std::string_view filename, const isa::Machine& m, int runs,
                               const WhileRun& run);
// The exit path that an exit after `e` completed iterations takes.
std::string exit_path_name(const PipelineResult& r, std::uint32_t e);

} // namespace nesshi::sched
