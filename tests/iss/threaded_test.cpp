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
    REQUIRE(ka.wait == kb.wait);
    REQUIRE(ka.wait_cycles == kb.wait_cycles);
    REQUIRE(ka.words_received == kb.words_received);
    REQUIRE(ka.words_sent == kb.words_sent);
    REQUIRE(a.fault_report() == b.fault_report());
    if (a.status() == Status::Blocked) REQUIRE(a.blocked_channel() == b.blocked_channel());
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

namespace {

// A loop through FIFO bundles, all inside threaded chains when their gates pass: the entry
// falls into a bundle receiving two words (also the branch's target), the next falls into a
// send, the send bundle falls into the branch.
std::vector<Bundle> fifo_chain_program() {
    return {{op("li", 1, 0, 0, 6), op("fli", 1, 0, 0, 0x3f800000)},
            {op("addi", 7, 7, 0, 1)},
            {op("addi", 8, 8, 0, 1)},
            {op("recv", 2, 0, 0, 0), op("recv", 3, 0, 0, 0), op("fadd", 2, 2, 1)},
            {op("add", 4, 2, 3), op("addi", 1, 1, 0, -1)},
            {op("send", 0, 4, 0, 1), op("add", 5, 5, 4)},
            {op("bnez", 0, 1, 0, 3), op("xor", 6, 6, 4), op("fadd", 4, 2, 1)},
            {op("halt")}};
}

// One processor with its input and output channel.
struct Rig {
    std::unique_ptr<Processor> p;
    QueueChannel in, out;
    NullTracer t;
    Rig(const char* machine, Engine e, bool traced, size_t out_capacity)
        : p(make_proc(machine, fifo_chain_program(), e)), out(out_capacity) {
        p->attach_channel(0, &in);
        p->attach_channel(1, &out);
        if (traced) p->set_tracer(&t);
    }
};

} // namespace

// FIFO bundles inside chains: whenever the fast gate does not pass (a word not there yet, none at
// all, no room, a closed channel) the general gate decides, so the waits, blocks and deadlock
// messages are those of the general loop (a tracer forces it) and of the checked engine.
TEST_CASE("FIFO bundles in threaded chains stop, wait, block and deadlock as the general loop") {
    struct Case {
        const char* what;
        uint32_t words;       // fed in all
        bool close;           // the input is closed once all are fed
        size_t out_capacity;  // 1: a send blocks until the host drains
    };
    for (const Case& cs : {Case{"all words, unbounded output", 12, false, SIZE_MAX},
                           Case{"all words, one-word output", 12, true, 1},
                           Case{"a word short: deadlock on a half-fed bundle", 11, true, SIZE_MAX},
                           Case{"two words short: deadlock on an empty channel", 10, true, 1}}) {
        for (const char* machine : {"os", "os-real"}) {
            for (int mode = 0; mode < 3; ++mode) {
                for (uint64_t k : {1, 2, 3, 7, 1000}) {
                    INFO(cs.what << ", " << machine << ", mode " << mode << ", " << k);
                    std::vector<std::unique_ptr<Rig>> rigs;
                    rigs.push_back(std::make_unique<Rig>(machine, Engine::Fast, false, cs.out_capacity));
                    rigs.push_back(std::make_unique<Rig>(machine, Engine::Fast, true, cs.out_capacity));
                    rigs.push_back(std::make_unique<Rig>(machine, Engine::Checked, false, cs.out_capacity));
                    uint32_t fed = 0;
                    for (int turn = 0; turn < 3000; ++turn) {
                        const Status st0 = rigs[0]->p->status();
                        if (st0 == Status::Halted || st0 == Status::Faulted) break;
                        for (auto& r : rigs) {
                            if (mode == 0) r->p->run(k);
                            else if (mode == 1) r->p->step(k, 3 * k); // a cycle limit: a half-fed bundle waits
                            else r->p->run_until(r->p->cycle() + k);
                        }
                        for (size_t i = 1; i < rigs.size(); ++i) require_same(*rigs[0]->p, *rigs[i]->p);
                        // The host, alike for all: a word now and then, ready 0 to 4 cycles
                        // ahead; the output drained every third turn.
                        if (turn % 2 == 0 && fed < cs.words) {
                            for (auto& r : rigs) r->in.feed(100 + fed, r->p->cycle() + (fed * 7) % 5);
                            ++fed;
                            if (fed == cs.words && cs.close)
                                for (auto& r : rigs) r->in.close();
                        }
                        if (turn % 3 == 0)
                            for (auto& r : rigs) r->out.drain_all();
                    }
                    const Status st = rigs[0]->p->status();
                    REQUIRE((st == Status::Halted || st == Status::Faulted));
                    if (cs.words < 12) {
                        REQUIRE(st == Status::Faulted);
                        REQUIRE(rigs[0]->p->fault()->kind == FaultKind::Deadlock);
                    } else {
                        REQUIRE(st == Status::Halted);
                    }
                }
            }
        }
    }
}

// Plenty of words and room: every gate passes, the chain goes through the FIFO bundles, and the
// run ends exactly as the general loop's.
TEST_CASE("a threaded chain runs through FIFO bundles whose gates pass") {
    for (const char* machine : {"os", "os-real"}) {
        INFO(machine);
        Rig fast(machine, Engine::Fast, false, SIZE_MAX), ref(machine, Engine::Fast, true, SIZE_MAX);
        for (Rig* r : {&fast, &ref}) {
            for (uint32_t w = 0; w < 12; ++w) r->in.feed(w * 3, 0);
            r->in.close();
        }
        REQUIRE(fast.p->run() == Status::Halted);
        REQUIRE(ref.p->run() == Status::Halted);
        require_same(*fast.p, *ref.p);
        REQUIRE(fast.out.drain_all() == ref.out.drain_all());
    }
}
