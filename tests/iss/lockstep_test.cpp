// Lock-step agreement of the two engines on every example and kernel, identical statistics
// across repeated runs, FIFO timing and shared memory.
#include "helpers.hpp"

#include "assembler/assembler.hpp"
#include "iss/lockstep.hpp"
#include "iss/stats.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace nesshi;
using namespace nesshi::iss;
using namespace nesshi::iss::test;
namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::shared_ptr<const Program> assemble(const fs::path& path) {
    std::string text = read_text(path);
    std::string machine = "os";
    if (text.rfind("# machine:", 0) == 0) {
        std::string first = text.substr(10, text.find('\n') - 10);
        machine = first.substr(first.find_first_not_of(' '));
        while (!machine.empty() && (machine.back() == ' ' || machine.back() == '\r')) machine.pop_back();
    }
    isa::Machine m = isa::load_machine(machine);
    assembler::AsmOptions opts;
    auto r = assembler::assemble_file(path.string(), m, opts);
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    return load_program(r.object, m);
}

std::vector<fs::path> sources(const std::string& dir) {
    std::vector<fs::path> out;
    fs::path root = fs::path(NESSHI_SOURCE_DIR) / dir;
    if (!fs::exists(root)) return out;
    for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.path().extension() == ".s") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

// Both engines with identical channels: channel 0 gets `words` then closes, others collect.
struct Pair {
    Processor fast, checked;
    std::vector<std::unique_ptr<QueueChannel>> chans;
    Pair(std::shared_ptr<const Program> prog, const std::vector<uint32_t>& words)
        : fast(prog, Engine::Fast), checked(prog, Engine::Checked) {
        for (Processor* p : {&fast, &checked})
            for (const auto& d : prog->ops()) {
                auto k = d.instr.info().kind;
                if (k != isa::Kind::Recv && k != isa::Kind::Send) continue;
                if (p->channel(d.imm)) continue;
                auto q = std::make_unique<QueueChannel>();
                if (k == isa::Kind::Recv) {
                    for (uint32_t w : words) q->feed(w);
                    q->close();
                }
                p->attach_channel(d.imm, q.get());
                chans.push_back(std::move(q));
            }
    }
};

} // namespace

TEST_CASE("the fast and checked engines agree bundle by bundle on every example and kernel") {
    auto files = sources("examples");
    auto kernels = sources("kernels");
    files.insert(files.end(), kernels.begin(), kernels.end());
    REQUIRE(!files.empty());
    for (const fs::path& f : files) {
        INFO(f.string());
        auto prog = assemble(f);
        Pair pair(prog, {3, 10, 20, 30, 40, 50, 60, 70, 80, 90});
        LockstepResult r = run_lockstep(pair.fast, pair.checked, 1'000'000);
        // Kernels fed with arbitrary words stop when the input runs dry or a made-up address is
        // out of range (the same fault in both engines); the point is that the engines never
        // diverge and no dynamic scheduling rule is broken on the way.
        if (r.fault) {
            INFO(format_fault(*prog, *r.fault));
            CHECK(r.fault->kind != FaultKind::Divergence);
            CHECK(r.fault->kind != FaultKind::InflightRead);
            CHECK(r.fault->kind != FaultKind::WritePorts);
            CHECK(r.fault->kind != FaultKind::DupWrite);
            CHECK(r.fault->kind != FaultKind::WriteOrder);
        } else {
            CHECK(r.status == Status::Halted);
        }
    }
}

namespace {

// Everything a stop exposes: the two engines must agree on it.
void require_same_state(const Processor& a, const Processor& b) {
    REQUIRE(a.status() == b.status());
    if (a.status() == Status::Faulted) { // and the state after it, below: the same in both engines
        CHECK(a.fault()->kind == b.fault()->kind);
        CHECK(a.fault()->cycle == b.fault()->cycle);
        CHECK(a.fault()->pc == b.fault()->pc);
    }
    REQUIRE(a.pc() == b.pc());
    REQUIRE(a.cycle() == b.cycle());
    for (uint16_t r = 0; r < kNumRegs; ++r) REQUIRE(a.reg(r) == b.reg(r));
    const auto ia = a.inflight(), ib = b.inflight();
    REQUIRE(ia.size() == ib.size());
    for (size_t i = 0; i < ia.size(); ++i) {
        CHECK(ia[i].reg == ib[i].reg);
        CHECK(ia[i].value == ib[i].value);
        CHECK(ia[i].lands == ib[i].lands);
    }
    const Counters &ka = a.counters(), &kb = b.counters();
    CHECK(ka.exec == kb.exec);
    CHECK(ka.wait == kb.wait);
    CHECK(ka.taken == kb.taken);
    CHECK(ka.stall == kb.stall);
    CHECK(ka.wait_cycles == kb.wait_cycles);
    CHECK(ka.bubble_cycles == kb.bubble_cycles);
    CHECK(ka.stall_cycles == kb.stall_cycles);
    for (int f = 0; f < isa::kNumRegFiles; ++f) CHECK(a.write_histogram(f) == b.write_histogram(f));
    CHECK(a.memory().hash() == b.memory().hash());
}

// Stalls every other access by 2 cycles: memory stalls end a run in the middle.
struct Alternate : CacheModel {
    uint32_t n = 0;
    uint32_t access(uint32_t, uint32_t, bool) override { return (n++ & 1) * 2; }
};

} // namespace

// The fast engine issues runs of plain bundles in an inner loop; the checked engine issues one
// bundle per turn of the general loop. Stopped after any number of bundles or at any cycle, so
// also inside a run, both must leave the same state.
TEST_CASE("stopped anywhere, the fast engine's runs leave the state the checked engine does") {
    auto files = sources("examples");
    auto kernels = sources("kernels");
    files.insert(files.end(), kernels.begin(), kernels.end());
    files.push_back(fs::path(NESSHI_SOURCE_DIR) / "tests/iss/programs/runs.s");
    for (const fs::path& f : files) {
        auto prog = assemble(f);
        for (uint64_t chunk : {2, 3, 5, 8, 13, 1000}) {
            for (int mode = 0; mode < 3; ++mode) {
                const bool by_cycle = mode == 1, stalls = mode == 2;
                INFO(f.string() << (by_cycle ? ": run_until every " : ": step ") << chunk << (stalls ? ", stalls" : ""));
                Pair pair(prog, {3, 10, 20, 30, 40, 50, 60, 70, 80, 90});
                Alternate fast_model, checked_model;
                if (stalls)
                    for (const isa::MemoryDesc& m : prog->machine().memories) {
                        pair.fast.attach_cache(m.name, &fast_model);
                        pair.checked.attach_cache(m.name, &checked_model);
                    }
                for (int calls = 0; calls < 100'000; ++calls) {
                    Status s = by_cycle ? pair.fast.run_until(pair.fast.cycle() + chunk) : pair.fast.step(chunk);
                    if (by_cycle) pair.checked.run_until(pair.checked.cycle() + chunk);
                    else pair.checked.step(chunk);
                    require_same_state(pair.fast, pair.checked);
                    if (s != Status::Running) break;
                }
            }
        }
    }
}

TEST_CASE("lock-step reports a divergence") {
    auto prog = load_program(make_object(isa::load_machine("os"), {{op("li", 1, 0, 0, 1)}, {op("halt")}}),
                             isa::load_machine("os"));
    Processor a(prog, Engine::Fast), b(prog, Engine::Checked);
    b.set_reg(R(7), 3); // different state from the start
    LockstepResult r = run_lockstep(a, b, 100);
    REQUIRE(r.fault);
    CHECK(r.fault->kind == FaultKind::Divergence);
    CHECK(r.fault->message == "fast and checked engines diverge after this bundle: r7: fast 0x00000000, checked 0x00000003");
}

TEST_CASE("repeated runs give identical statistics") {
    for (const fs::path& f : sources("examples")) {
        INFO(f.string());
        auto prog = assemble(f);
        std::string first;
        for (int run = 0; run < 3; ++run) {
            Pair pair(prog, {3, 1, 2, 3});
            pair.fast.run(1'000'000);
            std::string json = stats_json(compute_stats(pair.fast)).dump();
            if (run == 0) first = json;
            CHECK(json == first);
        }
        Pair again(prog, {3, 1, 2, 3});
        again.checked.run(1'000'000);
        CHECK(stats_json(compute_stats(again.checked)).dump() == first);
    }
}

TEST_CASE("communication and wait cycles are counted apart from processing") {
    // recv (comm), addi (processing), send (comm), halt (processing)
    auto p = make_proc("os", {{op("recv", 1, 0, 0, 0)}, {op("addi", 1, 1, 0, 1)}, {op("send", 0, 1, 0, 1)}, {op("halt")}});
    QueueChannel in, out;
    in.feed(7, 5); // arrives in cycle 5
    p->attach_channel(0, &in);
    p->attach_channel(1, &out);
    REQUIRE(p->run() == Status::Halted);
    Stats s = compute_stats(*p);
    CHECK(s.wait_cycles == 5);
    CHECK(s.communication_cycles == 2);
    CHECK(s.processing_cycles == 2);
    CHECK(s.cycles == 9);
    CHECK(s.ilp == 1.0);
    CHECK(s.units[0].ops + s.units[1].ops == 2);
    CHECK(s.words_received == 1);
    CHECK(s.words_sent == 1);
}

TEST_CASE("write-port histogram counts writes in the cycle they land") {
    // fdiv (latency 4) in cycle 0 lands in cycle 4 with the two latency-1 writes of cycle 3.
    auto p = make_proc("ic", {{op("fdiv", 1, 2, 3)}, {op("nop")}, {op("nop")}, {op("fadd", 4, 2, 3), op("fadd", 5, 2, 3)},
                              {op("halt")}});
    REQUIRE(p->run() == Status::Halted);
    Stats s = compute_stats(*p);
    const PortStats& fp = s.ports[1];
    CHECK(fp.writes == 3);
    REQUIRE(fp.write_hist.size() == 4);
    CHECK(fp.write_hist[3] == 1);
    CHECK(fp.write_hist[0] == 4);
}

TEST_CASE("processors share a host-provided global memory") {
    isa::Machine ic = isa::load_machine("ic");
    auto global = std::make_shared<PagedMemory>(ic.memory_at(0x10000000, 4)->size);
    global->write(0x40, 4, 1234);
    auto prog = load_program(make_object(ic, {{op("li", 1, 0, 0, 0x10000040)}, {op("lw", 2, 1, 0, 0)},
                                              {op("addi", 2, 2, 0, 1)}, {op("sw", 0, 1, 2, 4)}, {op("halt")}}),
                             ic);
    Processor a(prog), b(prog);
    a.attach_memory("global", global);
    b.attach_memory("global", global);
    REQUIRE(a.run() == Status::Halted);
    REQUIRE(b.run() == Status::Halted);
    CHECK(a.reg(R(2)) == 1235);
    CHECK(global->read(0x44, 4) == 1235);
    CHECK(global->pages_in_use() == 1);
    CHECK_THROWS(a.attach_memory("nowhere", global));
}

TEST_CASE("run_until stops at the cycle asked for and can continue") {
    auto p = make_proc("os", {{op("li", 1, 0, 0, 100)}, {op("addi", 1, 1, 0, uint32_t(-1))}, {op("bnez", 0, 1, 0, 1)},
                              {op("halt")}});
    uint64_t stops = 0;
    while (p->run_until(p->cycle() + 7) == Status::Running) ++stops;
    CHECK(p->status() == Status::Halted);
    CHECK(p->cycle() == 1 + 200 + 1);
    CHECK(stops == 28);
}

TEST_CASE("the load/store TLB never serves stale storage or skips a cache model") {
    isa::Machine ic = isa::load_machine("ic");
    const uint32_t gsize = ic.memory_at(0x10000000, 4)->size;
    // A loop that loads global word 0x40 into r2 four times, then halts.
    auto prog = load_program(make_object(ic, {{op("li", 1, 0, 0, 0x10000040)},
                                              {op("li", 3, 0, 0, 4)},
                                              {op("lw", 2, 1, 0, 0)},
                                              {op("addi", 3, 3, 0, uint32_t(-1))},
                                              {op("bnez", 0, 3, 0, 2)},
                                              {op("halt")}}),
                             ic);
    auto first = std::make_shared<PagedMemory>(gsize), second = std::make_shared<PagedMemory>(gsize);
    first->write(0x40, 4, 111);
    second->write(0x40, 4, 222);
    Processor p(prog);
    p.attach_memory("global", first);
    REQUIRE(p.step(4) == Status::Running); // the page is in the TLB now
    CHECK(p.reg(R(2)) == 111);
    p.attach_memory("global", second); // replacing the storage empties the TLB
    REQUIRE(p.run() == Status::Halted);
    CHECK(p.reg(R(2)) == 222);

    // A stall model on the region: every access pays, none is served by the TLB.
    struct Stall : CacheModel {
        uint32_t calls = 0;
        uint32_t access(uint32_t, uint32_t, bool) override { return ++calls, 3; }
    } stall;
    Processor q(prog);
    q.attach_memory("global", first);
    q.attach_cache("global", &stall);
    REQUIRE(q.run() == Status::Halted);
    CHECK(stall.calls == 4);
    CHECK(q.counters().stall_cycles == 12);
}

TEST_CASE("write-port histogram: a halting bundle's writes and idle cycles") {
    // Bundle 1 writes two registers and halts: its writes never land in a later cycle, so, as
    // for every halt, they are not counted; the cycles spent idle count as zero-write cycles.
    auto p = make_proc("os", {{op("li", 1, 0, 0, 5)}, {op("li", 2, 0, 0, 6), op("li", 3, 0, 0, 7), op("halt")}});
    REQUIRE(p->run() == Status::Halted);
    Stats s = compute_stats(*p);
    const PortStats& ir = s.ports[0];
    REQUIRE(ir.write_hist.size() == 2);
    CHECK(ir.write_hist[0] == 1); // cycle 0: nothing lands
    CHECK(ir.write_hist[1] == 1); // cycle 1: li r1 lands
    CHECK(ir.writes == 1);

    auto q = make_proc("os", {{op("li", 1, 0, 0, 5)}, {op("li", 2, 0, 0, 6)}, {op("halt")}});
    REQUIRE(q->step(1) == Status::Running);
    q->idle_until(q->cycle() + 5); // the host parks the processor for 5 cycles
    REQUIRE(q->run() == Status::Halted);
    Stats t = compute_stats(*q);
    const PortStats& qr = t.ports[0];
    uint64_t cycles = 0;
    for (uint64_t n : qr.write_hist) cycles += n;
    CHECK(qr.write_hist[1] == 2); // li r1 and li r2 land
    CHECK(cycles == t.cycles);
}

// A memory fault stops the processor after the faulting bundle issued everything but the faulting
// access, in both engines: latency-1 results land (written in place or through the queue by the
// fast engine, always queued by the checked one), longer ones stay in flight, the other stores are
// done. Lock-step compares that state, not only the fault.
TEST_CASE("after a memory fault both engines keep the rest of the faulting bundle") {
    const isa::Machine m = isa::load_machine("os");
    auto prog = load_program(make_object(m, {{op("li", 1, 0, 0, 0x100), op("li", 6, 0, 0, 7)},
                                             {op("fli", 2, 0, 0, 0x40a00000u), op("li", 3, 0, 0, 9), op("mov", 4, 3),
                                              op("fdiv", 7, 2, 2)},
                                             {op("fli", 8, 0, 0, 0x3f800000u), op("lw", 5, 0, 0, 0xfffffff0u),
                                              op("sw", 0, 1, 6, 0)},
                                             {op("halt")}}),
                             m);
    Processor fast(prog, Engine::Fast), checked(prog, Engine::Checked);
    for (Processor* p : {&fast, &checked}) {
        INFO((p == &fast ? "fast" : "checked"));
        REQUIRE(p->run(100) == Status::Faulted);
        CHECK(p->fault()->kind == FaultKind::MemRange);
        CHECK(p->fault()->pc == 2);
        CHECK(p->reg(F(8)) == 0x3f800000u); // latency 1, same bundle as the fault
        CHECK(p->reg(R(5)) == 0);           // the faulting load wrote nothing
    }
    require_same_state(fast, checked);
    Processor a(prog, Engine::Fast), b(prog, Engine::Checked);
    const LockstepResult r = run_lockstep(a, b, 100);
    REQUIRE(r.fault);
    CHECK(r.fault->kind == FaultKind::MemRange);
}
