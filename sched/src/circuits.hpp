// Internal: recurrence bounds over a dependence graph (shared by the pipeliner and the loop report).
#pragma once

#include <cstdint>
#include <vector>

namespace nesshi::sched {

struct DepEdge {
    int from = 0, to = 0;
    int latency = 0;  // to issues >= from + latency - distance * II
    int distance = 0; // iterations
};

// No circuit has latency - II x distance > 0: every recurrence fits II.
bool ii_feasible(int nodes, const std::vector<DepEdge>& edges, int ii);
// The smallest feasible II (1 when the graph has no circuit).
int recurrence_mii(int nodes, const std::vector<DepEdge>& edges);
// A circuit that is positive at ii (so it binds at ii + 1), as the edge indices along it; empty
// when none is.
std::vector<int> positive_circuit(int nodes, const std::vector<DepEdge>& edges, int ii);

} // namespace nesshi::sched
