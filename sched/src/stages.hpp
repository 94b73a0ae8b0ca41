// Internal: stage scheduling, a post-pass of the modulo scheduler. Moving an op by whole IIs keeps
// its row of the modulo reservation table, so every resource, port and landing rule the table
// was built under still holds; only the dependences decide how far it may move. Ops are moved
// to shorten register lifetimes (fewer copies, a smaller unroll, less register pressure) and the
// schedule's stage count (a shorter fill and drain), as in Eichenberger and Davidson's stage
// scheduling.
#pragma once

#include "sched/ddg.hpp"

#include <utility>
#include <vector>

namespace nesshi::sched {

// A value in a register: written by `def`, `latency` cycles after its issue, read by each use
// (op, iterations later).
struct StageValue {
    int def = 0;
    int latency = 1;
    std::vector<std::pair<int, int>> uses;
};

// The registers `values` occupy at `time` (each value's lifetime in whole IIs, summed), the
// measure shift_stages lowers.
int stage_registers(const std::vector<StageValue>& values, const std::vector<int>& time, int ii);

// `time` with ops moved by whole IIs wherever every edge still holds: to fewer stages first,
// fewer registers (stage_registers) second, shorter lifetimes in cycles third; never worse than
// `time` on any of them. One op moves at a time, as long as a move improves.
std::vector<int> shift_stages(const std::vector<Dep>& edges, const std::vector<StageValue>& values,
                              std::vector<int> time, int ii);

} // namespace nesshi::sched
