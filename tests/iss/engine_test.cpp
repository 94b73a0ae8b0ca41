// Bundle semantics, latencies and the pending-write queue, on both engines.
#include "helpers.hpp"

#include "iss/stats.hpp"

using namespace nesshi::iss;
using namespace nesshi::iss::test;

TEST_CASE("mov r0, r1 then mov r1, r0 in one bundle swaps") {
    for (Engine e : {Engine::Fast, Engine::Checked}) {
        auto p = make_proc("os", {{op("li", 0, 0, 0, 7), op("li", 1, 0, 0, 9)},
                                  {op("mov", 0, 1), op("mov", 1, 0)},
                                  {op("halt")}}, e);
        REQUIRE(p->run() == Status::Halted);
        CHECK(p->reg(R(0)) == 9);
        CHECK(p->reg(R(1)) == 7);
        CHECK(p->cycle() == 3);
    }
}

TEST_CASE("a result lands latency cycles after issue, earlier reads see the old value") {
    // os: fdiv latency 4. The fast engine lets a program read f1 early (old value);
    // the checked engine reports that read.
    std::vector<Bundle> prog = {
        {op("fli", 2, 0, 0, 0x40c00000u), op("fli", 3, 0, 0, 0x40000000u)}, // f2 = 6, f3 = 2
        {op("fdiv", 1, 2, 3)},                                              // cycle 1: lands 5
        {op("nop")}, {op("nop")},
        {op("fmov", 4, 1)},                                                 // cycle 4: old f1 (0)
        {op("fmov", 5, 1)},                                                 // cycle 5: new f1 (3)
        {op("halt")}};
    auto p = make_proc("os", prog);
    REQUIRE(p->step(2) == Status::Running);
    auto inflight = p->inflight();
    REQUIRE(inflight.size() == 1);
    CHECK(inflight[0].reg == F(1));
    CHECK(inflight[0].lands == 5);
    CHECK(inflight[0].value == 0x40400000u);
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(F(4)) == 0);
    CHECK(p->reg(F(5)) == 0x40400000u);

    auto c = make_proc("os", prog, Engine::Checked);
    REQUIRE(c->run() == Status::Faulted);
    CHECK(c->fault()->kind == FaultKind::InflightRead);
    CHECK(c->fault()->cycle == 4);
    CHECK(c->fault()->pc == 4);
}

TEST_CASE("stats count cycles, bundles, ops and ILP") {
    auto p = make_proc("os", {{op("li", 1, 0, 0, 3), op("li", 2, 0, 0, 0)},
                              {op("addi", 2, 2, 0, 1), op("addi", 1, 1, 0, uint32_t(-1)), op("fli", 1, 0, 0, 0)},
                              {op("bnez", 0, 1, 0, 1)},
                              {op("halt")}},
                       Engine::Fast, {{"start", 0}, {"loop", 1}, {"done", 3}});
    // loop: bundle 1 then bundle 2 (bnez r1 reads the r1 of bundle 1, landed)
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(R(2)) == 3);
    Stats s = compute_stats(*p);
    CHECK(s.cycles == 1 + 3 * 2 + 1);
    CHECK(s.bundles == s.cycles);
    CHECK(s.ops == 2 + 3 * 3 + 3 * 1 + 1);
    CHECK(s.taken_branches == 2);
    CHECK(s.regions.size() == 3);
    CHECK(s.regions[1].label == "loop");
    CHECK(s.regions[1].bundles == 6);
}

// The write-port histogram covers the cycles run: a run stopped at the cycle limit, blocked on
// a FIFO, or stopped by a fault before the bundle at cycle() issued had landed that cycle's
// writes already, and counted cycle() + 1 cycles (1001 for `sim --max-cycles 1000`).
TEST_CASE("the write-port histogram counts cycle() cycles however the run stops") {
    auto sum = [](const std::vector<uint64_t>& h) { uint64_t n = 0; for (uint64_t v : h) n += v; return n; };
    auto spin = [] {
        return std::vector<Bundle>{{op("li", 1, 0, 0, 0)}, {op("addi", 1, 1, 0, 1), op("fli", 1, 0, 0, 0), op("beqz", 0, 2, 0, 1)}};
    };
    for (Engine e : {Engine::Fast, Engine::Checked}) {
        auto p = make_proc("os", spin(), e);
        REQUIRE(p->run(1000) == Status::Running);
        REQUIRE(p->cycle() == 1000);
        for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) CHECK(sum(p->write_histogram(f)) == 1000);
        CHECK(p->write_histogram(0)[1] == 999); // li and 998 addi; the 1000th bundle's write lands in cycle 1000
        REQUIRE(p->run(500) == Status::Running); // and it continues exactly
        for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) CHECK(sum(p->write_histogram(f)) == 1500);
        // One bundle at a time, as the debugger steps.
        auto q = make_proc("os", spin(), e);
        for (int i = 0; i < 20; ++i) q->step(1);
        CHECK(q->cycle() == 20);
        for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) CHECK(sum(q->write_histogram(f)) == 20);
    }
    // Blocked on an empty channel after a result of latency 4 (fdiv) was issued: the ring writes landing at the stop.
    auto b = make_proc("os", {{op("fli", 2, 0, 0, 0x40000000), op("fli", 3, 0, 0, 0x40000000)},
                              {op("fdiv", 4, 2, 3)}, {op("nop")}, {op("nop")}, {op("nop")},
                              {op("recv", 1, 0, 0, 0)}, {op("halt")}});
    QueueChannel ch;
    b->attach_channel(0, &ch);
    REQUIRE(b->run() == Status::Blocked);
    for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) CHECK(sum(b->write_histogram(f)) == b->cycle());
    ch.feed(1);
    REQUIRE(b->run() == Status::Halted);
    for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) CHECK(sum(b->write_histogram(f)) == b->cycle());
    CHECK(b->write_histogram(1)[1] == 1); // the fdiv
    CHECK(b->write_histogram(1)[2] == 1); // the two fli
}
