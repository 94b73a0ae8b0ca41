// The one dependence graph: its bounds on hand-made graphs, and the block graph's edges.
#include "sched/ddg.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <string>

using namespace nesshi;

TEST_CASE("Ddg bounds: rec_mii rounds the largest latency per iteration up, max_ratio_circuit names it", "[unit][sched][ddg]") {
    // Circuit A (0 <-> 1): 7 cycles over 2 iterations = 3.5; circuit B (2 -> 2): 3 over 1.
    sched::Ddg g;
    g.nodes = 3;
    g.edges = {{0, 1, 4, 0}, {1, 0, 3, 2}, {2, 2, 3, 1}};
    CHECK(g.rec_mii() == 4);
    CHECK_FALSE(g.admits(3));
    CHECK(g.admits(4));
    const std::vector<int> c = g.max_ratio_circuit();
    const sched::CycleRatio r = g.ratio(c);
    CHECK(r.latency == 7);
    CHECK(r.distance == 2);
    CHECK(r.value() == 3.5);
    CHECK(g.ratio(g.critical()).value() > 3); // a circuit that needs more than 3
    // Without circuit A, B binds: 3 exactly.
    g.edges.resize(1);
    g.edges.push_back({2, 2, 3, 1});
    CHECK(g.rec_mii() == 3);
    CHECK(g.ratio(g.max_ratio_circuit()).value() == 3);
    // No circuit: II 1, nothing critical.
    g.edges.pop_back();
    CHECK(g.rec_mii() == 1);
    CHECK(g.critical().empty());
    CHECK(g.max_ratio_circuit().empty());
    // Longest paths: op 0's height is its edge to op 1 (4), op 1's depth the same.
    CHECK(g.longest_paths(4, true) == std::vector<int>{4, 0, 0});
    CHECK(g.longest_paths(4, false) == std::vector<int>{0, 4, 0});
}

TEST_CASE("block_ddg: true, anti and output edges with the exposed pipeline's latencies, memory and a branch after all", "[unit][sched][ddg]") {
    const isa::Machine m = isa::load_machine("os-real");
    // Nops between the ops keep the assembler's hazard checks quiet; the graph leaves them out.
    std::string text = "        .text\nstart:\n";
    for (const char* op : {"lw r3, 0(r1)", "addi r4, r3, 1", "addi r3, r2, 2", "sw r4, 0(r5)", "jmp start"})
        text += fmt::format("        {}\n        nop\n        nop\n        nop\n        nop\n        nop\n        nop\n", op);
    const assembler::AsmResult a = assembler::assemble_string(text, "t.s", m, {});
    INFO(a.diagnostics);
    REQUIRE(a.ok);
    std::vector<isa::Instr> ops;
    for (const auto& b : isa::decode_bundles(a.object))
        for (const isa::Instr& in : b)
            if (in.info().kind != isa::Kind::Nop) ops.push_back(in);
    REQUIRE(ops.size() == 5);
    const sched::Ddg g = sched::block_ddg(m, ops, 0);
    auto has = [&](int from, int to, int latency, sched::DepKind kind) {
        return std::any_of(g.edges.begin(), g.edges.end(), [&](const sched::Dep& e) {
            return e.from == from && e.to == to && e.latency == latency && e.distance == 0 && e.kind == kind;
        });
    };
    const int lw = static_cast<int>(m.latency_of(ops[0].info())), alu = static_cast<int>(m.latency_of(ops[1].info()));
    CHECK(has(0, 1, lw, sched::DepKind::True));
    CHECK(has(1, 2, 1 - alu, sched::DepKind::Anti));          // lands after the read issues
    CHECK(has(0, 2, lw + 1 - alu, sched::DepKind::Output));   // lands after the load's write
    CHECK(has(0, 3, 0, sched::DepKind::Memory));              // the store after the load
    CHECK(has(1, 3, alu, sched::DepKind::True));
    for (int i = 0; i < 4; ++i) CHECK(std::any_of(g.edges.begin(), g.edges.end(), [&](const sched::Dep& e) {
        return e.from == i && e.to == 4 && e.kind == sched::DepKind::Order;
    }));
    CHECK(g.rec_mii() == 1); // a block has no circuit
}
