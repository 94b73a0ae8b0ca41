#include "stages.hpp"

#include <algorithm>
#include <limits>
#include <tuple>

namespace nesshi::sched {

namespace {

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Cycles from a value's write to its last read (a new value may issue in the cycle of that read).
int lifetime(const StageValue& v, const std::vector<int>& time, int ii) {
    const int t0 = time[static_cast<std::size_t>(v.def)];
    int last = t0 + v.latency;
    for (const auto& [use, distance] : v.uses) last = std::max(last, time[static_cast<std::size_t>(use)] + distance * ii);
    return last - t0;
}

using Cost = std::tuple<int, int, long>; // stages, registers, lifetime cycles

Cost cost(const std::vector<StageValue>& values, const std::vector<int>& time, int ii) {
    const auto [lo, hi] = std::minmax_element(time.begin(), time.end());
    int regs = 0;
    long cycles = 0;
    for (const StageValue& v : values) {
        const int life = lifetime(v, time, ii);
        regs += std::max(1, (life + ii - 1) / ii);
        cycles += life;
    }
    return {floor_div(*hi, ii) - floor_div(*lo, ii) + 1, regs, cycles};
}

} // namespace

int stage_registers(const std::vector<StageValue>& values, const std::vector<int>& time, int ii) {
    int regs = 0;
    for (const StageValue& v : values) regs += std::max(1, (lifetime(v, time, ii) + ii - 1) / ii);
    return regs;
}

std::vector<int> shift_stages(const std::vector<Dep>& edges, const std::vector<StageValue>& values,
                              std::vector<int> time, int ii) {
    constexpr int kMaxShift = 8;   // stages an op may move at once
    constexpr int kMaxRounds = 32; // passes over the ops (each improves the cost, so this rarely binds)
    const int n = static_cast<int>(time.size());
    std::vector<std::vector<int>> in(static_cast<std::size_t>(n)), out(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < edges.size(); ++k)
        if (edges[k].from != edges[k].to) {
            out[static_cast<std::size_t>(edges[k].from)].push_back(static_cast<int>(k));
            in[static_cast<std::size_t>(edges[k].to)].push_back(static_cast<int>(k));
        }
    Cost best = cost(values, time, ii);
    for (int round = 0; round < kMaxRounds; ++round) {
        bool moved = false;
        for (int x = 0; x < n; ++x) {
            const int t = time[static_cast<std::size_t>(x)];
            int lo = -kMaxShift, hi = kMaxShift; // shifts in whole IIs that keep every edge
            for (int k : in[static_cast<std::size_t>(x)]) {
                const Dep& e = edges[static_cast<std::size_t>(k)];
                const int need = time[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii - t;
                lo = std::max(lo, -floor_div(-need, ii)); // ceil(need / ii)
            }
            for (int k : out[static_cast<std::size_t>(x)]) {
                const Dep& e = edges[static_cast<std::size_t>(k)];
                hi = std::min(hi, floor_div(time[static_cast<std::size_t>(e.to)] - t - e.latency + e.distance * ii, ii));
            }
            int chosen = 0;
            for (int s = lo; s <= hi; ++s) {
                if (s == 0) continue;
                time[static_cast<std::size_t>(x)] = t + s * ii;
                if (const Cost c = cost(values, time, ii); c < best) {
                    best = c;
                    chosen = s;
                }
            }
            time[static_cast<std::size_t>(x)] = t + chosen * ii;
            moved = moved || chosen != 0;
        }
        if (!moved) break;
    }
    return time;
}

} // namespace nesshi::sched
