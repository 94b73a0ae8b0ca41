// The fast engine's threaded runs (src/chain.hpp): a chain of jumps, and every exit from it
// leaves the state the general loop leaves.
#include "helpers.hpp"

#include <pthread.h>

using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {

// A tracer makes the fast engine take the general loop, one bundle per turn (no threaded runs).
struct NullTracer : Tracer {
    void on_cycle(const Program&, const CycleEvent&) override {}
};

void require_same(const Processor& a, const Processor& b) {
    REQUIRE(a.status() == b.status());
    REQUIRE(a.cycle() == b.cycle());
    REQUIRE(a.pc() == b.pc());
    for (uint16_t r = 0; r < kNumRegs; ++r) REQUIRE(a.reg(r) == b.reg(r));
    const auto ia = a.inflight(), ib = b.inflight();
    REQUIRE(ia.size() == ib.size());
    for (size_t i = 0; i < ia.size(); ++i) {
        REQUIRE(ia[i].reg == ib[i].reg);
        REQUIRE(ia[i].value == ib[i].value);
        REQUIRE(ia[i].lands == ib[i].lands);
    }
    for (int f = 0; f < nesshi::isa::kNumRegFiles; ++f) REQUIRE(a.write_histogram(f) == b.write_histogram(f));
    const Counters &ka = a.counters(), &kb = b.counters();
    REQUIRE(ka.exec == kb.exec);
    REQUIRE(ka.stall == kb.stall);
    REQUIRE(ka.taken == kb.taken);
    REQUIRE(ka.stall_cycles == kb.stall_cycles);
    REQUIRE(ka.bubble_cycles == kb.bubble_cycles);
}

// A loop of straight bundles: loads and a store, a latency-4 fdiv landing inside the run, a
// latency-1 write read later in its own bundle (queued, not written in place), a taken branch.
std::vector<Bundle> loop_program() {
    return {{op("li", 1, 0, 0, 0), op("li", 2, 0, 0, 64), op("fli", 2, 0, 0, 0x40000000), op("fli", 3, 0, 0, 0x40400000)},
            {op("li", 9, 0, 0, 23), op("li", 5, 0, 0, 0)},
            {op("addi", 1, 1, 0, 1), op("lw", 3, 2, 0, 0), op("fdiv", 4, 2, 3), op("fadd", 5, 4, 2)},
            {op("sw", 0, 2, 1, 4), op("add", 4, 3, 1), op("fmul", 2, 2, 3), op("fadd", 6, 6, 5)},
            {op("addi", 5, 5, 0, 1), op("add", 6, 5, 6)},
            {op("xor", 7, 7, 1), op("lw", 8, 2, 0, 4), op("fadd", 7, 7, 2)},
            {op("bne", 0, 1, 9, 2), op("add", 10, 10, 8)},
            {op("halt")}};
}

} // namespace

TEST_CASE("every exit from a threaded run leaves the general loop's state") {
    for (const char* machine : {"os", "os-real"}) {
        for (uint64_t k : {1, 2, 3, 5, 7, 11, 1000}) {
            INFO(machine << ", " << k << " bundles or cycles at a time");
            for (bool by_cycles : {false, true}) {
                auto fast = make_proc(machine, loop_program());
                auto ref = make_proc(machine, loop_program());
                NullTracer t;
                ref->set_tracer(&t);
                for (int turn = 0; turn < 400 && fast->status() != Status::Halted; ++turn) {
                    if (by_cycles) {
                        fast->run(k);
                        ref->run(k);
                    } else {
                        fast->step(k);
                        ref->step(k);
                    }
                    require_same(*fast, *ref);
                }
                REQUIRE(fast->status() == Status::Halted);
                REQUIRE(fast->reg(R(1)) == 23);
            }
        }
    }
}

namespace {

struct LongRun {
    std::unique_ptr<Processor> p;
    Status st = Status::Running;
};

void* run_long(void* arg) {
    auto* lr = static_cast<LongRun*>(arg);
    lr->st = lr->p->run();
    return nullptr;
}

} // namespace

// GCC 12 has no musttail: were a handler's call of the next one not a jump, a straight run of
// 40,000 bundles would take at least 16 bytes of stack per operation, far more than 128 KiB.
TEST_CASE("a long straight run is a chain of jumps (runs on a small stack)") {
    constexpr uint32_t kBundles = 40000;
    std::vector<Bundle> code(kBundles, Bundle{op("addi", 1, 1, 0, 1), op("xor", 2, 2, 1), op("fadd", 1, 1, 2)});
    code.push_back({op("halt")});
    LongRun lr{make_proc("os", std::move(code))};
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, 128 * 1024);
    pthread_t th;
    REQUIRE(pthread_create(&th, &attr, run_long, &lr) == 0);
    pthread_join(th, nullptr);
    pthread_attr_destroy(&attr);
    CHECK(lr.st == Status::Halted);
    CHECK(lr.p->reg(R(1)) == kBundles);
    CHECK(lr.p->cycle() == kBundles + 1);
}

// Chains stop before a bundle behind the FIFO gate and at a transfer outside the code; the
// general loop then decides (waits, blocks, the bad-pc fault) as it would have.
TEST_CASE("a threaded chain stops at a FIFO-gated target and at a bad pc as the general loop") {
    // A loop whose branch target receives: blocks on the empty channel, then runs on.
    auto fifo_loop = [] {
        return std::vector<Bundle>{{op("li", 1, 0, 0, 3)},
                                   {op("recv", 2, 0, 0, 0)},
                                   {op("add", 3, 3, 2), op("addi", 1, 1, 0, -1)},
                                   {op("fli", 1, 0, 0, 0x3f800000)},
                                   {op("bnez", 0, 1, 0, 1)},
                                   {op("jr", 0, 3)}}; // to pc 60 (10 + 20 + 30): outside the code
    };
    for (const char* machine : {"os", "os-real"}) {
        INFO(machine);
        auto fast = make_proc(machine, fifo_loop());
        auto ref = make_proc(machine, fifo_loop());
        NullTracer t;
        ref->set_tracer(&t);
        QueueChannel cf, cr;
        fast->attach_channel(0, &cf);
        ref->attach_channel(0, &cr);
        for (uint32_t w : {10u, 20u, 30u}) {
            REQUIRE(fast->run() == Status::Blocked);
            REQUIRE(ref->run() == Status::Blocked);
            require_same(*fast, *ref);
            cf.feed(w, fast->cycle() + 2);
            cr.feed(w, ref->cycle() + 2);
        }
        REQUIRE(fast->run() == Status::Faulted);
        REQUIRE(ref->run() == Status::Faulted);
        REQUIRE(fast->fault()->kind == FaultKind::BadPc);
        REQUIRE(fast->fault_report() == ref->fault_report());
        require_same(*fast, *ref);
    }
}
