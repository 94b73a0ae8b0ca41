// Internal to the pipeliner: modulo schedules of a dependence graph at one II, by the iterative
// modulo scheduler (op orders by height, critical first or perturbed, an optional stage limit);
// --exact's search of every table is pipeline_exact.hpp.
#pragma once

#include "pipeline_graph.hpp"

#include "isa/machine.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace nesshi::sched::pipe {

constexpr int kAttemptsPerII = 12; // schedules tried at one II before the next (different op orders)

// The registers of file `f` op x writes.
int writes_to(const isa::Instr& x, int f);

struct Schedule {
    int ii = 0;
    std::vector<int> time;          // issue cycle of each node in the flat schedule (iteration 0)
    isa::Instr branch, counter;     // loop control in the kernel: counter decrement and branch
    int counter_row = 0;
    bool loop_control = true;       // false for a while loop: its exit test, in the last row, is the branch

    // Stages (iterations in flight) of a normalised schedule.
    int stages() const {
        int st = 1;
        for (int t : time) st = std::max(st, t / ii + 1);
        return st;
    }

    // Shifts every time by whole stages so the earliest op issues in cycle 0 of its stage 0.
    void normalise() {
        const int lo = *std::min_element(time.begin(), time.end());
        const int shift = lo >= 0 ? -(lo / ii) * ii : ((-lo + ii - 1) / ii) * ii;
        for (int& t : time) t += shift;
    }
};

// One attempt of the iterative modulo scheduler at `ii`: attempt 0 orders ops by height alone,
// attempts 1 to kAttemptsPerII - 1 break near-ties at random, later ones put critical ops (least
// slack) first. `exit_node`: a while loop's exit test (then there is no counted loop control);
// `stages` > 0: only schedules of at most that many stages.
std::optional<Schedule> modulo_schedule(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch,
                                        const isa::Instr& counter, int attempt = 0, int exit_node = -1, int stages = 0);

// Whether schedule `s` keeps every rule of the iterative scheduler's reservation table (slots,
// ports, landings and the back edge, induction flights, a while loop's exit in the last row)
// and every dependence.
bool table_admits(const Graph& g, const isa::Machine& m, const Schedule& s, int exit_node);

} // namespace nesshi::sched::pipe
