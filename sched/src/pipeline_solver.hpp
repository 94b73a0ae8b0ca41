// Internal to the pipeliner: the shortest iteration at an II, found by z3 (Boolean and
// pseudo-Boolean constraints). The iterative scheduler places ops one at a time by priority; on a
// full reservation table that often leaves the iteration far longer than its longest path (the
// IC's triangle loop on ic-real: 113 cycles on a 68-cycle path), and every run of a loop pays
// about that length to fill and drain. This search takes the table's rules as constraints and
// asks for ever shorter iterations.
#pragma once

#include "pipeline_graph.hpp"
#include "pipeline_search.hpp"

#include "isa/machine.hpp"

#include <cstdint>
#include <optional>

namespace nesshi::sched::pipe {

// The solver's budget per search, in z3's resource units (about 0.7 s on this project's
// 2-core machine): deterministic, so the same source gives the same code on any machine.
constexpr std::uint64_t kSolverBudget = 5'000'000;

// The iteration's length: the cycle its last write lands in, from the first issue.
int iteration_length(const Graph& g, const Schedule& s);

// What one iteration's dependences alone allow, at any II: `length`, its longest path (the last
// op's latency included), which no schedule's iteration is shorter than; `latest_start`, the
// longest path into any op, so a schedule at II has at least latest_start / II + 1 stages.
struct IterationBounds {
    int length = 0, latest_start = 0;
    int fewest_stages(int ii) const { return latest_start / ii + 1; }
};
IterationBounds iteration_bounds(const Graph& g, const isa::Machine& m);

// A modulo schedule at found.ii (same loop control rows) whose iteration is shorter than
// `found`'s, as short as the solver finds within `budget` (z3's resource units, so the result
// does not depend on the machine's speed or load); none when it finds none. Every schedule
// returned passes `table_admits`. `exit_node`: a while loop's exit test, in the last row.
std::optional<Schedule> shortest_schedule(const Graph& g, const isa::Machine& m, const Schedule& found, int exit_node,
                                          std::uint64_t budget);

} // namespace nesshi::sched::pipe
