// The latency-hazard analysis: straight line, loops, branches, jr, late writes.
#include "support.hpp"

#include <catch2/catch.hpp>

using namespace nesshi;
using test::assemble;

TEST_CASE("latency-1 results are readable by the next bundle, reads in a bundle see old values", "[hazard]") {
    CHECK(assemble("li r1, 1\naddi r2, r1, 1\nhalt\n").ok);
    CHECK(assemble("{ mov r0, r1 ; mov r1, r0 }\nhalt\n").ok);
    CHECK(assemble("{ add r1, r1, r1 ; fadd f1, f1, f1 }\n{ add r1, r1, r1 ; fadd f1, f1, f1 }\nhalt\n").ok);
}

TEST_CASE("multi-cycle results: straight line, loop back edge, taken branch", "[hazard]") {
    auto straight = assemble("fdiv f1, f2, f3\nfadd f4, f1, f1\nhalt\n");
    CHECK_FALSE(straight.ok);
    CHECK(straight.diagnostics.find("f1 is read before its new value lands: 'fdiv' was issued 1 cycle earlier") !=
          std::string::npos);
    CHECK(straight.diagnostics.find("test.s:1:1: note: f1 is written here") != std::string::npos);
    CHECK(assemble("fdiv f1, f2, f3\nnop\nnop\nnop\nfadd f4, f1, f1\nhalt\n").ok);
    // Back edge: the read at the loop top is 2 cycles after the fdiv at the bottom.
    auto loop = assemble("top: fadd f4, f1, f1\n{ fdiv f1, f2, f3 ; bnez r1, top }\nhalt\n");
    CHECK_FALSE(loop.ok);
    CHECK(loop.diagnostics.find("test.s:1:6: error: f1 is read") != std::string::npos);
    // Taken path skips the padding; fall-through is fine.
    auto br = assemble("{ fdiv f1, f2, f3 ; beqz r1, t }\nnop\nnop\nnop\nt: fadd f4, f1, f1\nhalt\n");
    CHECK_FALSE(br.ok);
    // A halt ends the path; unconditional jumps have no fall-through.
    CHECK(assemble("{ fdiv f1, f2, f3 ; halt }\nfadd f4, f1, f1\nhalt\n").ok);
    CHECK(assemble("{ fdiv f1, f2, f3 ; jmp t }\nfadd f4, f1, f1\nt: nop\nnop\nnop\nhalt\n").ok);
}

TEST_CASE("jr is followed conservatively to return points and labels", "[hazard]") {
    auto r = assemble("jal r31, f\nfadd f4, f1, f1\nhalt\nf: { fdiv f1, f2, f3 ; jr r31 }\n");
    CHECK_FALSE(r.ok);
    CHECK(r.diagnostics.find("test.s:2:1: error: f1 is read") != std::string::npos);
}

// Indirect jumps reach their targets through one node of the flow graph: 20,000 lines
// `Lk: jr r1` used to make an edge from every jr to every label (400 million edges, out of
// memory). The hub must not change what reaches a target: the union over the jumps, delays kept.
TEST_CASE("indirect jumps go through one node: linear in jumps plus targets", "[hazard]") {
    std::string text;
    for (int k = 0; k < 20000; ++k) text += "L" + std::to_string(k) + ": jr r1\n";
    const auto many = assemble(text + "halt\n");
    CHECK(many.ok);
    CHECK(many.warnings == 0);
    // An fdiv (4 cycles on os) before either jr is still in flight at every target; with enough
    // padding before the jump it has landed on every path.
    const std::string targets = "a: fadd f4, f1, f1\nhalt\nb: fadd f5, f1, f1\nhalt\n";
    const auto early = assemble("{ fdiv f1, f2, f3 ; li r1, 0 }\njr r1\nnop\nnop\n" + targets);
    CHECK_FALSE(early.ok);
    CHECK(early.errors == 2);
    CHECK(early.diagnostics.find("test.s:5:4: error: f1 is read before its new value lands: 'fdiv' was issued 2 "
                                 "cycles earlier") != std::string::npos);
    CHECK(assemble("{ fdiv f1, f2, f3 ; li r1, 0 }\nnop\nnop\njr r1\n" + targets).ok);
    CHECK(assemble("{ fdiv f1, f2, f3 ; li r1, 0 }\nnop\njr r1\n" + targets).errors == 2);
}

TEST_CASE("late writes: same register and write ports across bundles", "[hazard]") {
    auto dup = assemble("fdiv f1, f2, f3\nnop\nnop\nfadd f1, f4, f5\nhalt\n");
    CHECK_FALSE(dup.ok);
    CHECK(dup.diagnostics.find("f1 is written twice in one cycle") != std::string::npos);
    auto ports = assemble("{ fdiv f1, f2, f3 ; fdiv f4, f5, f6 }\nnop\nnop\nfadd f7, f8, f9\nhalt\n");
    CHECK_FALSE(ports.ok);
    CHECK(ports.diagnostics.find("3 writes land in one cycle: os has 2 FPRF write ports") != std::string::npos);
    CHECK(assemble("{ fdiv f1, f2, f3 ; fdiv f4, f5, f6 }\nnop\nnop\nfadd f7, f8, f9\nhalt\n", "ic").ok);
}

// Writes to one register land in issue order (the checked ISS's write-order and dup-write).
TEST_CASE("a write may not land before or with an earlier write of its register", "[hazard]") {
    auto before = assemble("fdiv f1, f2, f3\nfadd f1, f4, f5\nhalt\n");
    CHECK_FALSE(before.ok);
    CHECK(before.errors == 1);
    CHECK(before.diagnostics.find("test.s:2:1: error: f1 is written before an earlier write to it lands: this result "
                                  "lands in cycle +1, the earlier 'fdiv' in cycle +3") != std::string::npos);
    CHECK(before.diagnostics.find("test.s:1:1: note: earlier write of f1: issued 1 cycle before, latency 4, lands in "
                                  "cycle +3") != std::string::npos);
    // Strictly after, still in flight or not: accepted.
    CHECK(assemble("fdiv f1, f2, f3\nfdiv f1, f4, f5\nhalt\n").ok);
    CHECK(assemble("fdiv f1, f2, f3\nnop\nnop\nnop\nfadd f1, f4, f5\nhalt\n").ok);
    // Other registers, other files: no constraint.
    CHECK(assemble("fdiv f1, f2, f3\n{ fadd f2, f4, f5 ; li r1, 1 }\nhalt\n").ok);
    // In the same cycle: the same-cycle message only.
    auto same = assemble("fdiv f1, f2, f3\nnop\nnop\nfadd f1, f4, f5\nhalt\n");
    CHECK(same.errors == 1);
    CHECK(same.diagnostics.find("is written before") == std::string::npos);
    // Around the back edge.
    auto loop = assemble("top: fadd f1, f4, f5\n{ fdiv f1, f2, f3 ; bnez r1, top }\nhalt\n");
    CHECK(loop.errors == 1);
    CHECK(loop.diagnostics.find("test.s:1:6: error: f1 is written before an earlier write to it lands: this result "
                                "lands in cycle +1, the earlier 'fdiv' (around a back edge) in cycle +3") !=
          std::string::npos);
    // Through jr: every return point and label.
    auto jr = assemble("jal r31, f\nfadd f1, f4, f5\nhalt\nf: { fdiv f1, f2, f3 ; jr r31 }\n");
    CHECK(jr.diagnostics.find("test.s:2:1: error: f1 is written before") != std::string::npos);
    // One path lands with the fdiv, the taken one before it: one error, for the worse path.
    auto paths = assemble("fdiv f1, f2, f3\nbeqz r1, s\nnop\ns: fadd f1, f4, f5\nhalt\n");
    CHECK(paths.errors == 1);
    CHECK(paths.diagnostics.find("the earlier 'fdiv' in cycle +2") != std::string::npos);
    // One bundle: the ISS issues in slot order, so a lower slot's write is the earlier one.
    auto bundle = assemble("{ fdiv f1, f2, f3 ; fadd f1, f4, f5 }\nhalt\n");
    CHECK(bundle.errors == 1);
    CHECK(bundle.diagnostics.find("the 'fdiv' of a lower slot of this bundle in cycle +4") != std::string::npos);
    CHECK(assemble("{ fadd f1, f4, f5 ; fdiv f1, f2, f3 }\nhalt\n").ok);
    CHECK(assemble("{ fpu1: fdiv f1, f2, f3 ; fpu0: fadd f1, f4, f5 }\nhalt\n").ok);
}

TEST_CASE("long-latency presets expose pipelined units", "[hazard]") {
    auto r = assemble("fadd f1, f2, f3\nfmul f4, f1, f1\nhalt\n", "os-real");
    isa::Machine m = isa::load_machine("os-real");
    if (m.latency[int(isa::OpClass::FAdd)] > 1) CHECK_FALSE(r.ok);
    else CHECK(r.ok);
}
