// Stage scheduling (sched/src/stages.hpp): ops moved by whole IIs keep every dependence, and the
// schedule never gets more stages or more registers; a value read stages after its write gets
// its writer moved next to the read.
#include "stages.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

using namespace nesshi::sched;

namespace {

int stages(const std::vector<int>& time, int ii) {
    const auto [lo, hi] = std::minmax_element(time.begin(), time.end());
    auto fl = [&](int t) { return t >= 0 ? t / ii : -((-t + ii - 1) / ii); };
    return fl(*hi) - fl(*lo) + 1;
}

bool holds(const std::vector<Dep>& edges, const std::vector<int>& time, int ii) {
    for (const Dep& e : edges)
        if (time[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii > time[static_cast<std::size_t>(e.to)]) return false;
    return true;
}

} // namespace

TEST_CASE("a load issued stages before its use moves next to it", "[unit][sched][stages]") {
    // II 2: op 0 loads (latency 2) what op 3 reads at cycle 6; ops 1 and 2 form a chain to op 3.
    const int ii = 2;
    const std::vector<Dep> edges = {{0, 3, 2, 0}, {1, 2, 2, 0}, {2, 3, 4, 0}};
    const std::vector<StageValue> values = {{0, 2, {{3, 0}}}, {1, 2, {{2, 0}}}, {2, 4, {{3, 0}}}};
    const std::vector<int> before = {0, 0, 2, 6};
    const std::vector<int> after = shift_stages(edges, values, before, ii);
    CHECK(after == std::vector<int>{4, 0, 2, 6}); // 6 cycles (3 registers) -> 2 cycles (1)
    CHECK(stage_registers(values, before, ii) == 3 + 1 + 2);
    CHECK(stage_registers(values, after, ii) == 1 + 1 + 2);
    CHECK(holds(edges, after, ii));
}

TEST_CASE("a loop-carried read keeps its writer in range", "[unit][sched][stages]") {
    // A recurrence: op 1 reads op 0's value of the previous iteration (distance 1) and op 0
    // reads op 1's: neither may move a whole II away from the other, so nothing moves.
    const int ii = 4;
    const std::vector<Dep> edges = {{0, 1, 3, 1}, {1, 0, 1, 0}};
    const std::vector<StageValue> values = {{0, 3, {{1, 1}}}, {1, 1, {{0, 0}}}};
    REQUIRE(holds(edges, {1, 0}, ii));
    CHECK(shift_stages(edges, values, {1, 0}, ii) == std::vector<int>{1, 0});
}

TEST_CASE("stage scheduling keeps every edge and never costs stages or registers", "[unit][sched][stages]") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 300; ++trial) {
        const int ii = 1 + static_cast<int>(rng() % 6), n = 2 + static_cast<int>(rng() % 14);
        std::vector<int> time(static_cast<std::size_t>(n));
        for (int& t : time) t = static_cast<int>(rng() % 40);
        // Edges that the times satisfy: latency at most the gap (plus II per iteration of distance).
        std::vector<Dep> edges;
        std::vector<StageValue> values;
        for (int from = 0; from < n; ++from) {
            StageValue v;
            v.def = from;
            v.latency = 1 + static_cast<int>(rng() % 4);
            for (int to = 0; to < n; ++to) {
                if (to == from || rng() % 3 != 0) continue;
                const int distance = static_cast<int>(rng() % 2);
                const int gap = time[static_cast<std::size_t>(to)] + distance * ii - time[static_cast<std::size_t>(from)];
                if (gap < 0) continue;
                const int latency = std::min(gap, v.latency);
                edges.push_back({from, to, latency, distance});
                if (latency == v.latency) v.uses.emplace_back(to, distance);
            }
            if (!v.uses.empty()) values.push_back(v);
        }
        INFO("trial " << trial);
        REQUIRE(holds(edges, time, ii));
        const std::vector<int> after = shift_stages(edges, values, time, ii);
        CHECK(holds(edges, after, ii));
        CHECK(stages(after, ii) <= stages(time, ii));
        if (stages(after, ii) == stages(time, ii)) CHECK(stage_registers(values, after, ii) <= stage_registers(values, time, ii));
        for (std::size_t k = 0; k < time.size(); ++k) CHECK((after[k] - time[k]) % ii == 0); // rows kept
    }
}
