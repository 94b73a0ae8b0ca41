// Each fault class stops the run with its report; bad objects give clean load errors.
#include "helpers.hpp"

#include "iss/lockstep.hpp"

#include <cstdlib>
#include <fstream>

using namespace nesshi;
using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {
// The dynamic port conflict on a taken path (tests/iss/programs/port_conflict_branch.s): the
// fdiv issued in cycle 1 lands in cycle 5 with the two float writes of `target` (cycle 4).
std::vector<Bundle> port_conflict_program() {
    auto at = [](isa::Instr in, uint8_t slot) { in.slot = slot; return in; }; // os: iu0 iu1 fpu0 fpu1
    return {{at(op("fli", 2, 0, 0, 0x40c00000u), 3), at(op("fli", 3, 0, 0, 0x40000000u), 2), at(op("li", 5, 0, 0, 5), 0)},
            {at(op("fdiv", 9, 2, 3), 2)},
            {at(op("nop"), 0)},
            {at(op("jr", 0, 5), 0)},
            {at(op("halt"), 0)},
            {at(op("fadd", 1, 2, 3), 3), at(op("fmul", 4, 2, 3), 2)},
            {at(op("halt"), 0)}};
}

std::unique_ptr<Processor> port_conflict_proc(Engine e) {
    isa::Machine m = isa::load_machine("os");
    return std::make_unique<Processor>(load_program(make_object(m, port_conflict_program(), {{"target", 5}}, {}, true), m), e);
}

const Fault& run_to_fault(Processor& p) {
    REQUIRE(p.run(1000) == Status::Faulted);
    REQUIRE(p.fault());
    return *p.fault();
}
} // namespace

TEST_CASE("dynamic write-port conflict on a taken path: checked engine reports, fast engine trusts") {
    auto c = port_conflict_proc(Engine::Checked);
    const Fault& f = run_to_fault(*c);
    CHECK(f.kind == FaultKind::WritePorts);
    CHECK(f.cycle == 4);
    CHECK(f.pc == 5);
    std::string report = c->fault_report();
    CHECK(report == "fault: write-ports: 3 FPRF writes land in cycle 5; os has 2 FPRF write ports\n"
                    "  at cycle 4, pc 5 (target), test.s:6\n"
                    "  bundle 5: { fpu1: fadd f1, f2, f3 ; fpu0: fmul f4, f2, f3 }\n"
                    "  note: fdiv f9, f2, f3 (bundle 1, issued in cycle 1, test.s:2) writes f9 in cycle 5\n"
                    "  note: fadd f1, f2, f3 (bundle 5, issued in cycle 4, test.s:6) writes f1 in cycle 5\n"
                    "  note: fmul f4, f2, f3 (bundle 5, issued in cycle 4, test.s:6) writes f4 in cycle 5\n");
    auto fast = port_conflict_proc(Engine::Fast);
    CHECK(fast->run() == Status::Halted);
}

TEST_CASE("the committed object of the port-conflict program is what the builder makes") {
    isa::Machine m = isa::load_machine("os");
    isa::ObjectFile obj = make_object(m, port_conflict_program(), {{"target", 5}}, {}, true);
    obj.files = {"tests/iss/programs/port_conflict_branch.s"};
    obj.lines = {{0, 9}, {0, 10}, {0, 11}, {0, 12}, {0, 13}, {0, 14}, {0, 15}};
    std::string path = std::string(NESSHI_SOURCE_DIR) + "/tests/iss/programs/port_conflict_branch.o";
    const char* update = std::getenv("NESSHI_UPDATE_GOLDEN");
    if (update && std::string(update) == "1") isa::write_object_file(obj, path);
    CHECK(isa::read_object_file(path) == obj);
}

TEST_CASE("two writes of one register landing in the same cycle") {
    // fdiv f1 (latency 4) in cycle 0 and fadd f1 (latency 1) in cycle 3 both land in cycle 4.
    auto c = make_proc("os", {{op("fdiv", 1, 2, 3)}, {op("nop")}, {op("nop")}, {op("fadd", 1, 2, 3)}, {op("halt")}},
                       Engine::Checked);
    const Fault& f = run_to_fault(*c);
    CHECK(f.kind == FaultKind::DupWrite);
    CHECK(f.message == "f1 is written twice in cycle 4");
    CHECK(f.notes.size() == 2);
}

// Writes to one register land in program order. fdiv f1 (latency 4) then fadd f1 (latency 1)
// lands the newer value first and the older over it: the checked engine stops (write-order).
// A load stall between them moves the fadd, so the same code can land both in one cycle
// (dup-write) or in order. The assembler rejects this code (it lands out of order without
// stalls); stalls only delay later bundles, so they never reorder writes it accepts.
struct Stall : CacheModel {
    uint32_t cycles;
    explicit Stall(uint32_t n) : cycles(n) {}
    uint32_t access(uint32_t, uint32_t, bool) override { return cycles; }
};

TEST_CASE("writes to one register must land in program order whatever the stalls") {
    const std::vector<Bundle> code{{op("fdiv", 1, 2, 3), op("lw", 5, 0, 0, 0)}, {op("nop")}, {op("fadd", 1, 4, 5)},
                                   {op("halt")}};
    auto c = make_proc("os", code, Engine::Checked);
    const Fault& f = run_to_fault(*c);
    CHECK(f.kind == FaultKind::WriteOrder);
    CHECK(f.message == "f1 is written in cycle 3, before an earlier write to it lands in cycle 4");
    CHECK(f.notes.size() == 2);
    for (uint32_t stall : {1u, 2u}) { // fadd issues in cycle 2 + stall: lands with fdiv, then after it
        INFO("stall " << stall);
        auto p = make_proc("os", code, Engine::Checked);
        Stall model(stall);
        p->attach_cache(p->program().machine().memories[0].name, &model);
        if (stall == 1) CHECK(run_to_fault(*p).kind == FaultKind::DupWrite);
        else CHECK(p->run(100) == Status::Halted);
    }
}

// Stalls delay the bundles after the stalling one while results in flight land on time: code the
// assembler accepts (each write to a register lands after the earlier ones) keeps that order under
// any stall, but two fadds meant to land between the fdivs can be moved onto their cycle.
TEST_CASE("stalls keep accepted writes to one register in order but not within the write ports") {
    const std::vector<Bundle> ordered{{op("fdiv", 1, 2, 3), op("lw", 5, 0, 0, 0)}, {op("fdiv", 1, 4, 5)}, {op("nop")},
                                      {op("nop")}, {op("nop")}, {op("fadd", 1, 6, 7)}, {op("halt")}};
    const std::vector<Bundle> ports{{op("fdiv", 1, 2, 3), op("fdiv", 2, 4, 5), op("lw", 5, 0, 0, 0)},
                                    {op("fadd", 3, 4, 5), op("fadd", 4, 6, 7)}, {op("halt")}};
    for (uint32_t stall : {0u, 1u, 2u, 3u, 7u}) {
        INFO("stall " << stall);
        auto p = make_proc("os", ordered, Engine::Checked);
        Stall model(stall);
        p->attach_cache(p->program().machine().memories[0].name, &model);
        CHECK(p->run(100) == Status::Halted);
        auto q = make_proc("os", ports, Engine::Checked);
        q->attach_cache(q->program().machine().memories[0].name, &model);
        if (stall == 2) CHECK(run_to_fault(*q).kind == FaultKind::WritePorts); // the fadds land in cycle 4
        else CHECK(q->run(100) == Status::Halted);
    }
}

TEST_CASE("reading a register whose write is in flight") {
    auto c = make_proc("os", {{op("fdiv", 1, 2, 3)}, {op("fadd", 4, 1, 1)}, {op("halt")}}, Engine::Checked);
    const Fault& f = run_to_fault(*c);
    CHECK(f.kind == FaultKind::InflightRead);
    CHECK(f.message == "fadd reads f1 in cycle 1, but its write lands in cycle 4");
    REQUIRE(f.notes.size() == 2);
    CHECK(f.notes[1] == "producer: fdiv f1, f2, f3 (bundle 0, issued in cycle 0, test.s:1) writes f1 in cycle 4");
}

TEST_CASE("memory faults: out of range and misaligned, on both engines") {
    for (Engine e : {Engine::Fast, Engine::Checked}) {
        auto a = make_proc("os", {{op("li", 1, 0, 0, 0x00200000)}, {op("lw", 2, 1, 0, 0)}, {op("halt")}}, e);
        const Fault& f = run_to_fault(*a);
        CHECK(f.kind == FaultKind::MemRange);
        CHECK(f.message == "lw address 0x00200000 is outside every memory region for a 4-byte access");
        auto b = make_proc("os", {{op("li", 1, 0, 0, 2)}, {op("li", 2, 0, 0, 9)}, {op("sw", 0, 1, 2, 0)}, {op("halt")}}, e);
        const Fault& g = run_to_fault(*b);
        CHECK(g.kind == FaultKind::MemAlign);
        CHECK(g.pc == 2);
        CHECK(g.message == "sw address 0x00000002 is not aligned to a 4-byte access");
    }
}

TEST_CASE("a misaligned access to a page in the TLB faults") {
    struct Case {
        const char* mnemonic;
        uint32_t offset;
        bool store;
    };
    for (Engine e : {Engine::Fast, Engine::Checked})
        for (Case k : {Case{"lw", 2, false}, Case{"lh", 1, false}, Case{"lhu", 3, false}, Case{"flw", 1, false},
                       Case{"sw", 1, true}, Case{"sh", 3, true}, Case{"fsw", 2, true}}) {
            INFO(k.mnemonic << " at +" << k.offset);
            // The store allocates the page and the load then hits it in the TLB.
            auto p = make_proc("os", {{op("li", 1, 0, 0, 0x100), op("li", 3, 0, 0, 7)}, {op("sw", 0, 1, 3, 0)},
                                      {op("lw", 2, 1, 0, 0)},
                                      {k.store ? op(k.mnemonic, 0, 1, 3, k.offset) : op(k.mnemonic, 2, 1, 0, k.offset)},
                                      {op("halt")}},
                               e);
            const Fault& f = run_to_fault(*p);
            CHECK(f.kind == FaultKind::MemAlign);
            CHECK(f.pc == 3);
            CHECK(p->reg(R(2)) == 7);
        }
}

TEST_CASE("control leaving the code") {
    auto a = make_proc("os", {{op("jmp", 0, 0, 0, 7)}, {op("halt")}});
    CHECK(run_to_fault(*a).kind == FaultKind::BadPc);
    CHECK(a->fault()->message == "control transfer to pc 7, outside the code (bundles 0..1)");
    auto b = make_proc("os", {{op("nop")}, {op("nop")}});
    CHECK(run_to_fault(*b).message == "execution ran past the last bundle (1) without halt");
    auto c = make_proc("os", {{op("li", 1, 0, 0, uint32_t(-1))}, {op("jr", 0, 1)}, {op("halt")}});
    CHECK(run_to_fault(*c).message == "control transfer to pc 4294967295, outside the code (bundles 0..2)");
}

TEST_CASE("channels: missing, deadlock on a closed empty input, blocking on an open one") {
    auto a = make_proc("os", {{op("recv", 1, 0, 0, 3)}, {op("halt")}});
    CHECK(run_to_fault(*a).kind == FaultKind::NoChannel);

    QueueChannel closed;
    closed.close();
    auto b = make_proc("os", {{op("recv", 1, 0, 0, 0)}, {op("halt")}});
    b->attach_channel(0, &closed);
    CHECK(run_to_fault(*b).kind == FaultKind::Deadlock);

    QueueChannel open;
    auto c = make_proc("os", {{op("recv", 1, 0, 0, 0)}, {op("halt")}});
    c->attach_channel(0, &open);
    CHECK(c->run() == Status::Blocked);       // returns at once
    CHECK(c->cycle() == 0);
    CHECK(c->run_until(10) == Status::Blocked); // waits to the cycle asked for
    CHECK(c->cycle() == 10);
    CHECK(c->counters().wait_cycles == 10);
    open.feed(5, 14);                          // a word that arrives in cycle 14
    CHECK(c->run() == Status::Halted);
    CHECK(c->counters().wait_cycles == 14);
    CHECK(c->reg(R(1)) == 5);
    CHECK(c->cycle() == 16);
}

// { recv r1, 0 ; recv r2, 0 } fed one word on a closed channel can never issue: the front word is
// ready, the second will never come. It used to wait a cycle at a time to the cycle limit (and
// for ever in a step or lock-step, which had no limit inside a step).
TEST_CASE("a bundle receiving more words than its closed channel holds is a deadlock") {
    const isa::Machine os = isa::load_machine("os");
    const auto prog = load_program(make_object(os, {{op("recv", 1, 0, 0, 0), op("recv", 2, 0, 0, 0)}, {op("halt")}}), os);
    const std::string why = "recv on channel 0, which holds 1 of the 2 words this bundle receives from it and will "
                            "never be fed";
    for (Engine e : {Engine::Fast, Engine::Checked}) {
        QueueChannel ch;
        ch.feed(7);
        ch.close();
        Processor p(prog, e);
        p.attach_channel(0, &ch);
        CHECK(run_to_fault(p).kind == FaultKind::Deadlock);
        CHECK(p.fault()->message == why);
        CHECK(p.cycle() == 0);
        Processor q(prog, e);
        QueueChannel ch2;
        ch2.feed(7);
        ch2.close();
        q.attach_channel(0, &ch2);
        CHECK(q.step(1) == Status::Faulted);
        CHECK(q.fault()->message == why);
    }
    QueueChannel a, b;
    for (QueueChannel* ch : {&a, &b}) {
        ch->feed(7);
        ch->close();
    }
    Processor fast(prog, Engine::Fast), checked(prog, Engine::Checked);
    fast.attach_channel(0, &a);
    checked.attach_channel(0, &b);
    const LockstepResult r = run_lockstep(fast, checked, 1000);
    CHECK(r.status == Status::Faulted);
    REQUIRE(r.fault);
    CHECK(r.fault->kind == FaultKind::Deadlock);
    // Words that do arrive, later, are waited for as before.
    QueueChannel later;
    later.feed(7);
    later.feed(8, 5);
    later.close();
    Processor p(prog);
    p.attach_channel(0, &later);
    CHECK(p.run(1000) == Status::Halted);
    CHECK(p.reg(R(1)) == 7);
    CHECK(p.reg(R(2)) == 8);
    CHECK(p.counters().wait_cycles == 5);
}

// The same bundle on an open channel: the second word may still come from the host, so the
// processor waits, but a step and a lock-step run stop at their cycle limit inside that wait.
TEST_CASE("step and lock-step stop at their cycle limit in the middle of a wait") {
    const isa::Machine os = isa::load_machine("os");
    const auto prog = load_program(make_object(os, {{op("recv", 1, 0, 0, 0), op("recv", 2, 0, 0, 0)}, {op("halt")}}), os);
    QueueChannel ch;
    ch.feed(7);
    Processor p(prog);
    p.attach_channel(0, &ch);
    CHECK(p.step(1, 1000) == Status::Running);
    CHECK(p.cycle() == 1000);
    CHECK(p.pc() == 0);
    CHECK(p.counters().wait_cycles == 1000);
    ch.feed(8, 0);
    CHECK(p.step(1, 1000) == Status::Running);
    CHECK(p.pc() == 1);
    CHECK(p.step(1) == Status::Halted);
    CHECK(p.reg(R(2)) == 8);

    QueueChannel a, b;
    a.feed(7);
    b.feed(7);
    Processor fast(prog, Engine::Fast), checked(prog, Engine::Checked);
    fast.attach_channel(0, &a);
    checked.attach_channel(0, &b);
    const LockstepResult r = run_lockstep(fast, checked, 1000);
    CHECK(r.status == Status::Running);
    CHECK(!r.fault);
    CHECK(fast.cycle() == 1000);
    CHECK(checked.cycle() == 1000);
}

TEST_CASE("bad objects and programs give clean load errors") {
    isa::Machine os = isa::load_machine("os");
    SECTION("a bundle that breaks a static rule") {
        auto obj = make_object(isa::load_machine("ic"), {{op("fadd", 1, 2, 3), op("fadd", 4, 5, 6), op("fadd", 7, 8, 9)}});
        obj.machine = "os";
        obj.machine_fingerprint = os.fingerprint();
        REQUIRE_THROWS_WITH(load_program(obj, os), Catch::Contains("bundle 0 breaks a static rule of machine 'os'") &&
                                                        Catch::Contains("write-ports"));
    }
    SECTION("an illegal encoding") {
        auto obj = make_object(os, {{op("halt")}});
        obj.code[0] |= uint64_t{0x7f} << 56; // opcode 127
        REQUIRE_THROWS_WITH(load_program(obj, os), Catch::Contains("illegal encoding"));
    }
    SECTION("data outside memory") {
        // A loading problem like the others: load_program reports it, as LoadError documents,
        // so no Processor constructor ever throws it.
        auto obj = make_object(os, {{op("halt")}});
        obj.data.push_back({0x00300000, {1, 2, 3, 4}});
        REQUIRE_THROWS_AS(load_program(obj, os), LoadError);
        REQUIRE_THROWS_WITH(load_program(obj, os), Catch::StartsWith("data section at 0x00300000 (4 bytes) is outside every "
                                                                     "memory region of machine 'os'"));
        obj.data.back().address = 0x001ffffe; // straddles the end of the OS SRAM: the memory and the size it would need
        REQUIRE_THROWS_WITH(load_program(obj, os), Catch::EndsWith(": it starts in sram (0x00000000, 2097152 bytes), which "
                                                                   "would need 2097154 bytes to hold it"));
        obj.data.back() = {0x00300000, {}};    // an empty section occupies nothing
        REQUIRE_NOTHROW(Processor(load_program(obj, os)));
    }
    SECTION("an object for another machine") {
        auto obj = make_object(os, {{op("halt")}});
        REQUIRE_THROWS_WITH(load_program(obj, isa::load_machine("ic")), Catch::Contains("assembled for machine 'os'"));
    }
    SECTION("truncated and foreign files") {
        std::string path = "iss_test_bad.o";
        { std::ofstream(path) << "not an object"; }
        REQUIRE_THROWS_AS(load_program_file(path), LoadError);
        auto bytes = isa::write_object(make_object(os, {{op("halt")}}));
        bytes.resize(bytes.size() - 3);
        { std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size())); }
        REQUIRE_THROWS_AS(load_program_file(path), LoadError);
        std::remove(path.c_str());
    }
}
