// Internal to the pipeliner: --exact, every modulo reservation table of a counted loop at one II
// by a constraint model (exact_model.hpp), each handed to the caller until one is accepted.
#pragma once

#include "pipeline_graph.hpp"
#include "pipeline_search.hpp"

#include "isa/machine.hpp"

#include <chrono>
#include <cstdint>
#include <functional>

namespace nesshi::sched::pipe {

// Accepted: `accept` took a table. Exhausted: no table at this II passes the build's gate (the
// write ports across the kernel's back edge, for every kernel length it can choose) or each that
// did was refused. Timeout: the deadline came first.
enum class ExactOutcome { Accepted, Exhausted, Timeout };
struct ExactRun {
    ExactOutcome outcome = ExactOutcome::Exhausted;
    std::uint64_t nodes = 0;  // search nodes visited
    std::uint64_t tables = 0; // complete modulo schedules handed to accept
};

// The budget with which the pipeliner asks the model, at each II its search found nothing at,
// whether a table exists (the report says which: none exists, or one the search missed).
inline constexpr std::uint64_t kProofNodes = 5000;

// A counted loop's tables at `ii` (loop control in the kernel, the branch in its last row), each
// one handed to `accept` until it returns true. While loops are not searched (the caller keeps
// their heuristic schedule).
// `node_limit` > 0: Timeout after that many nodes too (a budget that gives the same answer on any host).
ExactRun exact_schedule(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter,
                        std::chrono::steady_clock::time_point deadline, const std::function<bool(const Schedule&)>& accept,
                        std::uint64_t node_limit = 0);

} // namespace nesshi::sched::pipe
