// Internal: the trip count a counted region states (`.trip MIN[, EXPECTED]`), and the whole run of
// its code in cycles at a trip count, from the code's shape. The pipeliner chooses among schedules
// by that figure, so it must be exact: tests/sched/trip_test.cpp compares it with the ISS.
#pragma once

#include "sched/pipeline.hpp"

#include <cstdint>
#include <string>
#include <string_view>

namespace nesshi::sched {

// `.trip MIN[, EXPECTED]`: every run has at least MIN iterations (a smaller count is the user's
// error, as with TI's .trip); schedules are compared at EXPECTED (default MIN).
struct TripDirective {
    int min = 0; // 0: no .trip
    int expected = 0;
    int line = 0;
};

// Parses the operands of a `.trip` line as written (split as the assembler reads operands; the
// columns place the caret). Throws base::Error at the offending operand.
TripDirective parse_trip(const std::string& text, std::string_view file, int line);

// The bundles of each part of a counted loop's code (Emitter::code), in program order:
//   [nops]                                              lead (without the guard)
//   [beqz TRIP, done]                                   guard
//   [slti; beqz pipe]                                   short path: N < min_pipelined ...
//   seq:   body; addi TRIP, -1; bnez TRIP, seq; jmp done  ... runs the sequential copy
//   pipe:  setup; prologue passes; entry nops;
//          kernel: unroll x groups copies of the II rows, each counting an iteration; beqz to
//          the exit of its rotation after each copy but the last, bnez back after the last;
//   exit of rotation unroll - 1 (falls out of the kernel), then those of 0, 1, ..., unroll - 2:
//          tail, and `jmp done` after each but the last laid out.
// Each ALU result is followed by nops until it lands; a taken branch costs the penalty more.
struct CountedShape {
    int alu_latency = 1;
    int penalty = 0;         // the machine's taken-branch bubble
    bool guard = true;       // the test for a trip count of 0
    bool short_path = true;  // trip counts below min_pipelined run the sequential copy
    int prologue_passes = 0, unroll = 1, ii = 1;
    int groups = 1;          // the kernel holds unroll x groups copies (Allocation::groups)
    int min_pipelined = 1;   // the fewest iterations the pipelined code runs
    int body = 0;            // bundles of the sequential copy's ops (each with the nops to its latency)
    int setup = 0;           // bundles from `pipe` to the prologue (the counter's set-up)
    int entry_nops = 0;
    int tail = 0;            // bundles of an exit: epilogue, drain, `li TRIP, 0`
    int lead = 0;            // nops first, for results of the code before the region (no guard)
};

// Cycles from the region's first bundle to its `done` label for `trips` iterations, without
// memory stalls (the same for every schedule: each iteration's accesses run once on any path),
// and where they go (RunParts, in the public header with TripChoice).
RunParts whole_run_parts(const CountedShape& s, std::int64_t trips);
std::int64_t whole_run_cycles(const CountedShape& s, std::int64_t trips);

} // namespace nesshi::sched
