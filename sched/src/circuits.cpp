#include "circuits.hpp"

#include <algorithm>

namespace nesshi::sched {

namespace {
// Longest-path relaxation; returns the edge of the last relaxation of a round past n (a positive
// circuit's), or -1 when the lengths settle.
int relax(int n, const std::vector<DepEdge>& edges, int ii, std::vector<int>* pred) {
    std::vector<std::int64_t> dist(static_cast<std::size_t>(n), 0);
    if (pred) pred->assign(static_cast<std::size_t>(n), -1);
    int last = -1;
    for (int round = 0; round <= n; ++round) {
        last = -1;
        for (std::size_t k = 0; k < edges.size(); ++k) {
            const DepEdge& e = edges[k];
            const std::int64_t w = e.latency - static_cast<std::int64_t>(ii) * e.distance;
            if (dist[static_cast<std::size_t>(e.from)] + w > dist[static_cast<std::size_t>(e.to)]) {
                dist[static_cast<std::size_t>(e.to)] = dist[static_cast<std::size_t>(e.from)] + w;
                if (pred) (*pred)[static_cast<std::size_t>(e.to)] = static_cast<int>(k);
                last = static_cast<int>(k);
            }
        }
        if (last < 0) return -1;
    }
    return last;
}
} // namespace

bool ii_feasible(int nodes, const std::vector<DepEdge>& edges, int ii) { return relax(nodes, edges, ii, nullptr) < 0; }

int recurrence_mii(int nodes, const std::vector<DepEdge>& edges) {
    int ii = 1;
    while (!ii_feasible(nodes, edges, ii)) ++ii;
    return ii;
}

std::vector<int> positive_circuit(int nodes, const std::vector<DepEdge>& edges, int ii) {
    std::vector<int> pred;
    const int e = relax(nodes, edges, ii, &pred);
    if (e < 0) return {};
    // Walk predecessors n times to land inside the circuit, then collect it.
    int v = edges[static_cast<std::size_t>(e)].to;
    for (int k = 0; k < nodes; ++k) v = edges[static_cast<std::size_t>(pred[static_cast<std::size_t>(v)])].from;
    std::vector<int> circuit;
    int u = v;
    do {
        const int pe = pred[static_cast<std::size_t>(u)];
        circuit.push_back(pe);
        u = edges[static_cast<std::size_t>(pe)].from;
    } while (u != v && circuit.size() <= edges.size());
    std::reverse(circuit.begin(), circuit.end());
    return circuit;
}

} // namespace nesshi::sched
