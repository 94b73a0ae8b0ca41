// sched/src/exact_model.hpp: the Gecode model of --exact on problems small enough to count
// their tables by hand.
#include "exact_model.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <set>
#include <vector>

// No using-directive: the unity build puts this file in one batch with the other tests.
using nesshi::sched::pipe::ModelOp;
using nesshi::sched::pipe::ModelProblem;
using nesshi::sched::pipe::ModelSearch;
using nesshi::sched::pipe::search_tables;

namespace {

// `n` ops on `slots` slots that take anything, ports never short.
ModelProblem ops_on_slots(int n, int slots) {
    ModelProblem p;
    p.slot_count = slots;
    p.read_ports = {4, 4};
    p.write_ports = {4, 4};
    ModelOp any;
    any.slots = (1u << slots) - 1;
    p.ops.assign(static_cast<std::size_t>(n), any);
    p.branch = any;
    return p;
}

// Three ops at II 2 on two slots, the branch in row 1: row 0 holds two ops and row 1 one, so
// (the counter among them) each table is which op goes to row 1.
ModelProblem three_in_two_rows() {
    ModelProblem p = ops_on_slots(3, 2);
    p.ii = 2;
    return p;
}

auto soon() { return std::chrono::steady_clock::now() + std::chrono::seconds(10); }

} // namespace

TEST_CASE("exact model: every table once, a refused one excluded, then exhausted", "[unit][sched][exact]") {
    const ModelProblem p = three_in_two_rows();
    std::set<std::vector<int>> seen;
    int calls = 0;
    const ModelSearch s = search_tables(p, {}, soon(), [&](const std::vector<int>& rows, const std::vector<int>& stages) {
        ++calls;
        seen.insert(rows);
        CHECK(stages == std::vector<int>{0, 0, 0}); // no edges: the least stages
        return false;
    });
    CHECK(s.outcome == ModelSearch::Exhausted);
    CHECK(calls == 3); // no table handed over twice, across the restarts
    CHECK(seen == std::set<std::vector<int>>{{0, 0, 1}, {0, 1, 0}, {1, 0, 0}});
    int second = 0;
    CHECK(search_tables(p, {}, soon(), [&](const std::vector<int>&, const std::vector<int>&) { return ++second == 2; }).outcome ==
          ModelSearch::Accepted);
}

TEST_CASE("exact model: slots by Hall sets, edges as stages, a full port, no time", "[unit][sched][exact]") {
    ModelProblem p = three_in_two_rows();
    // Ops 0 and 1 take only slot 0: never in one row, so the counter (op 2) is in row 0.
    p.ops[0].slots = p.ops[1].slots = 0b01;
    // 0 -> 1 with latency 3: op 1 issues 3 cycles after op 0 at least.
    p.edges.push_back({0, 1, 3, 0});
    std::vector<std::vector<int>> tables;
    const ModelSearch s = search_tables(p, {}, soon(), [&](const std::vector<int>& rows, const std::vector<int>& stages) {
        CHECK(rows[2] == 0);
        CHECK(rows[0] != rows[1]);
        CHECK((rows[1] + 2 * stages[1]) - (rows[0] + 2 * stages[0]) >= 3);
        tables.push_back(rows);
        return false;
    });
    CHECK(s.outcome == ModelSearch::Exhausted);
    CHECK(tables.size() == 2);
    // One write port on file 0 with latency 1 writes from all three ops: 3 landings in 2 rows.
    ModelProblem full = three_in_two_rows();
    full.write_ports = {1, 4};
    for (ModelOp& op : full.ops) op.writes = {1, 0};
    CHECK(search_tables(full, {}, soon(), [](const std::vector<int>&, const std::vector<int>&) { return true; }).outcome ==
          ModelSearch::Exhausted);
    // A deadline already passed: Timeout, nothing handed over.
    CHECK(search_tables(p, {}, std::chrono::steady_clock::now(), [](const std::vector<int>&, const std::vector<int>&) {
              FAIL("no table expected");
              return true;
          }).outcome == ModelSearch::Timeout);
}

TEST_CASE("exact model: a straight block, its length the II, results landed by its end", "[unit][sched][exact]") {
    // Three ops on one slot, the second needing the first's 3-cycle result: 0 at 0, 2 at 1 or
    // 2, 1 at 3, landing by 4. No branch.
    ModelProblem p = ops_on_slots(3, 1);
    p.ops[0].latency = 3;
    p.edges.push_back({0, 1, 3, 0});
    p.has_branch = false;
    p.straight = true;
    auto at = [&](int length) {
        p.ii = length;
        p.latest = {length - 3, length - 1, length - 1};
        return p;
    };
    CHECK_FALSE(nesshi::sched::pipe::tables_may_exist(at(3), {}));
    std::set<std::vector<int>> seen;
    const ModelSearch s = search_tables(at(4), {}, soon(), [&](const std::vector<int>& rows, const std::vector<int>& stages) {
        seen.insert(rows);
        CHECK(stages == std::vector<int>{0, 0, 0});
        return false;
    });
    CHECK(s.outcome == ModelSearch::Exhausted);
    CHECK(seen == std::set<std::vector<int>>{{0, 3, 1}, {0, 3, 2}});
    // A node budget stops the search the same way on every host.
    CHECK(search_tables(at(40), {}, soon(), [](const std::vector<int>&, const std::vector<int>&) { return false; }, 5).outcome ==
          ModelSearch::Timeout);
}
