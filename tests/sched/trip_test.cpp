// `.trip MIN[, EXPECTED]` (sched/pipeline.hpp, TripChoice): the whole-run cycles the pipeliner
// chooses by equal the ISS's, the choice changes where more stages lose, the code drops the paths
// the minimum makes dead and still equals its sequential meaning, and bad values are errors.
#include "sched/pipeline.hpp"
#include "sched/random_loop.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/differential.hpp"
#include "iss/processor.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <random>
#include <string>

using namespace nesshi;

namespace {

// `text` with `directive` on the line after its `.pipeline r9`.
std::string with_line(const std::string& text, const std::string& directive) {
    const std::size_t at = text.find('\n', text.find(".pipeline r9")) + 1;
    return text.substr(0, at) + "        " + directive + "\n" + text.substr(at);
}

// `text` with a label `t_start` before its region: in sched::with_trip's programs the label is on
// the `li r9, N` (and its nops) that comes just before the region's code.
std::string labelled(const std::string& text) {
    const std::size_t at = text.rfind('\n', text.find(".pipeline r9")) + 1;
    return text.substr(0, at) + "t_start:\n" + text.substr(at);
}

// Cycles from the region's first bundle (after t_start's `li r9, N`) to `__sa_done`, on the ISS.
std::uint64_t region_cycles(const std::string& program, const isa::Machine& m) {
    const assembler::AsmResult a = assembler::assemble_string(program, "t.s", m, {});
    REQUIRE(a.ok);
    std::optional<std::uint32_t> start, done;
    for (const isa::Symbol& s : a.object.symbols) {
        if (s.kind != isa::SymbolKind::Code) continue;
        if (s.name == "t_start") start = s.value;
        if (s.name == "__sa_done") done = s.value;
    }
    REQUIRE((start && done));
    iss::Processor p(iss::load_program(a.object, m));
    while (p.pc() != *start) REQUIRE(p.step() == iss::Status::Running);
    const std::uint64_t c0 = p.cycle();
    while (p.pc() != *done) REQUIRE(p.step() == iss::Status::Running);
    const auto li = std::max<std::uint64_t>(1, m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
    return p.cycle() - c0 - li;
}

std::optional<std::string> verify(const isa::Machine& m, const sched::PipelineResult& r) {
    iss::DiffOptions d;
    d.registers = r.source_registers;
    return sched::verify(r, "t.sa", m, sched::verification_trips(r),
                         [&](const isa::ObjectFile& a, const isa::ObjectFile& b) { return iss::run_differential(a, b, m, d); });
}

// A loop over two 64-word arrays whose loaded value is read again at the end of a chain of
// `chain` dependent float operations: a long lifetime, so many kernel copies at a small II.
std::string long_body(const isa::Machine& m, int chain, int words = 64) {
    std::string body = "        flw   %a, xs(r1)\n        fmul  %c0, %a, f0\n";
    for (int k = 1; k < chain; ++k) body += fmt::format("        fadd  %c{}, %c{}, f1\n", k, k - 1);
    body += fmt::format("        fmul  %z, %c{}, %a\n        fsw   %z, ys(r1)\n", chain - 1);
    return fmt::format(R"(        .data {2:#x}
xs:     .space {0}
ys:     .space {0}
        .text
        li r1, 0
        li r9, 8
        fli f0, 0.5
        fli f1, 1.25
        .pipeline r9
{1}        addi r1, r1, 4
        .endpipeline
        halt
)", 4 * words, body, m.memories.at(0).base);
}

} // namespace

TEST_CASE(".trip: the whole-run cycles the choice is made by equal the ISS's", "[unit][sched][trip]") {
    std::mt19937_64 rng(2026);
    for (const char* name : {"os", "os-real", "ic", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        for (int k = 0; k < 8; ++k) {
            const std::string loop = k < 2 ? long_body(m, 4 + 6 * k, 512) : sched::random_linear_loop(rng(), m, 3 + 3 * k);
            // The minimum and the count run: with and without the short-trip path, with remainders.
            for (const auto& [min, runs] : {std::pair{1, 1}, {1, 3}, {1, 9}, {2, 37}, {40, 40}, {40, 45}, {64, 64}}) {
                const std::string text = labelled(with_line(loop, fmt::format(".trip {}, {}", min, runs)));
                INFO(name << " loop " << k << ", .trip " << min << ", " << runs << ":\n" << text);
                const sched::PipelineResult r = sched::pipeline_source(text, "t.sa", m, {});
                REQUIRE(r.loops[0].trip);
                const std::string run = sched::with_trip(r, m, static_cast<std::uint32_t>(runs)).pipelined;
                CHECK(static_cast<std::int64_t>(region_cycles(run, m)) == r.loops[0].trip->chosen.cycles);
            }
        }
    }
}

TEST_CASE(".trip chooses fewer stages where the whole run is shorter, and the code stays correct", "[unit][sched][trip]") {
    for (const char* name : {"os-real", "ic", "ic-real"}) { // on os the MII's schedule is the fastest
        const isa::Machine m = isa::load_machine(name);
        INFO(name);
        const std::string plain = labelled(long_body(m, 12));
        const sched::PipelineResult before = sched::pipeline_source(plain, "t.sa", m, {});
        // A trip just too short for the first schedule's pipeline: it runs the sequential copy.
        const int trips = before.min_pipelined_trip - 1;
        REQUIRE(trips >= 2);
        const std::string text = with_line(plain, fmt::format(".trip {}", trips));
        const sched::PipelineResult after = sched::pipeline_source(text, "t.sa", m, {});
        REQUIRE(after.loops[0].trip);
        const sched::TripChoice& c = *after.loops[0].trip;
        // Without .trip: the first schedule at the MII, which is what the report compares with.
        CHECK(before.ii == before.mii);
        CHECK((c.first.ii == before.ii && c.first.stages == before.stages && c.first.unroll == before.unroll));
        CHECK(c.chosen.cycles < c.first.cycles);
        // Why: the first schedule runs the whole trip through the sequential copy.
        CHECK(c.first.sequential_iterations == trips);
        CHECK(c.chosen.sequential_iterations < trips);
        CHECK(c.chosen.kernel + c.chosen.fill_drain + c.chosen.outside == c.chosen.cycles);
        CHECK(after.stages < before.stages);
        // Measured: both files run the trip; the one chosen by .trip takes fewer cycles.
        const auto cycles_of = [&](const std::string& t) {
            return region_cycles(sched::with_trip(sched::pipeline_source(t, "t.sa", m, {}), m, static_cast<std::uint32_t>(trips)).pipelined, m);
        };
        CHECK(cycles_of(text) < cycles_of(plain));
        CHECK(static_cast<std::int64_t>(cycles_of(text)) == c.chosen.cycles);
        CHECK(verify(m, after) == std::nullopt);
        CHECK(after.report.find(fmt::format("#   whole run at {} trips: II ", trips)) != std::string::npos);
    }
}

TEST_CASE(".trip drops the zero-trip test and the short-trip path, and verifies only counts it allows", "[unit][sched][trip]") {
    const isa::Machine m = isa::load_machine("os-real");
    const std::string text = with_line(long_body(m, 12), ".trip 40");
    const sched::PipelineResult r = sched::pipeline_source(text, "t.sa", m, {});
    CHECK(r.min_trip == 40);
    CHECK(r.min_pipelined_trip <= 40);
    CHECK(r.code.find("beqz r9") == std::string::npos);
    CHECK(r.code.find("slti") == std::string::npos);
    CHECK(r.code.find("__sa_seq:") == std::string::npos); // each kernel copy can leave: no remainder to run alone
    for (std::uint32_t t : sched::verification_trips(r)) CHECK(t >= 40);
    CHECK(verify(m, r) == std::nullopt);
    // Without .trip the same loop keeps both (the byte-identical default).
    const sched::PipelineResult plain = sched::pipeline_source(long_body(m, 12), "t.sa", m, {});
    CHECK(plain.code.find("beqz r9, __sa_done") != std::string::npos);
    CHECK(plain.code.find("slti") != std::string::npos);
    CHECK(!plain.loops[0].trip);
}

TEST_CASE("without its zero-trip test a region may start with nops for results of the code before it", "[unit][sched][trip]") {
    // The fadd reads f0 late in the sequential meaning, in the prologue's first bundle pipelined.
    const isa::Machine m = isa::load_machine("os-real"); // fdiv: 12 cycles
    const std::string text = R"(        .data 0x1000
xs:     .space 256
ys:     .space 256
zs:     .space 256
        .text
        li    r1, 0
        li    r9, 8
        fli   f0, 0.5
        fli   f1, 1.25
        nop
        nop
t_start:
        fdiv  f0, f0, f1
        nop
        .pipeline r9
        .trip 8
        flw   %a, xs(r1)
        fmul  %b, %a, %a
        fmul  %d, %b, %b
        fsw   %d, ys(r1)
        fadd  %e, f0, f1
        fsw   %e, zs(r1)
        addi  r1, r1, 4
        .endpipeline
        halt
)";
    sched::PipelineResult r;
    REQUIRE_NOTHROW(r = sched::pipeline_source(text, "t.sa", m, {}));
    REQUIRE(r.loops[0].trip);
    CHECK(r.code.find("        nop\n__sa_pipe:\n") != std::string::npos); // f0 lands first
    CHECK(r.code.find("beqz r9") == std::string::npos);
    // From t_start: the fdiv and the nop, then the region with its nops.
    CHECK(static_cast<std::int64_t>(region_cycles(sched::with_trip(r, m, 8).pipelined, m)) - 2 == r.loops[0].trip->chosen.cycles);
    CHECK(verify(m, r) == std::nullopt);
}

TEST_CASE("a bad .trip is an error at its operand", "[unit][sched][trip]") {
    const isa::Machine os = isa::load_machine("os");
    const auto err = [&](const std::string& directive) {
        try {
            sched::pipeline_source(with_line(long_body(os, 2), directive), "t.sa", os, {});
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(err(".trip 0"), Catch::StartsWith("t.sa:10:15: error: the minimum trip count must be an integer from 1 to "
                                                 "2147483647 (got '0')"));
    CHECK_THAT(err(".trip x"), Catch::StartsWith("t.sa:10:15: error: the minimum trip count must be"));
    CHECK_THAT(err(".trip -3"), Catch::Contains("(got '-3')"));
    CHECK_THAT(err(".trip 8, 4"), Catch::StartsWith("t.sa:10:18: error: the expected trip count 4 is below the minimum 8"));
    CHECK_THAT(err(".trip"), Catch::StartsWith("t.sa:10:9: error: .trip takes the minimum trip count"));
    CHECK_THAT(err(".trip 1, 2, 3"), Catch::Contains(".trip MIN[, EXPECTED]"));
    CHECK_THAT(err(".trip 4\n        .trip 5"), Catch::StartsWith("t.sa:11: error: .trip given twice (first at line 10)"));
    CHECK_THAT(err(".trip 99999999999"), Catch::Contains("(got '99999999999')"));
    CHECK_THROWS_WITH(sched::pipeline_source(".pipeline while\n.trip 4\nbeqz r1, exit\n.endpipeline\n", "t.sa", os, {}),
                      Catch::StartsWith("t.sa:2: error: .trip belongs in a counted .pipeline region"));
}

TEST_CASE("with .trip the sequential copy runs one iteration as the modulo schedule places it", "[unit][sched][trip]") {
    const isa::Machine m = isa::load_machine("os-real");
    const std::string text = R"(        .data 0x1000
xs:     .space 256
ys:     .space 256
        .text
        li    r1, 0
        li    r9, 40
        fli   f0, 2.5
        .pipeline r9
        .trip 1, 40
        flw   %x, xs(r1)
        flw   %y, ys(r1)
        fmul  %t, f0, %x
        fadd  %s, %t, %y
        fsw   %s, ys(r1)
        addi  r1, r1, 4
        .endpipeline
        halt
)";
    const sched::PipelineResult r = sched::pipeline_source(text, "t.sa", m, {});
    REQUIRE(r.min_pipelined_trip > 1); // a short trip to run
    const std::size_t from = r.code.find("__sa_seq:\n"), to = r.code.find("        addi r9, r9, -1\n");
    REQUIRE((from != std::string::npos && to != std::string::npos && from < to));
    const std::string body = r.code.substr(from, to - from);
    // One op after another it takes 2 + 2 + 3 + 3 + 1 + 1 = 12 bundles; as scheduled, 11 (the step
    // beside the fmul, the later accesses offset by -4).
    CHECK(std::count(body.begin(), body.end(), '\n') - 1 < 12);
    CHECK(body.find("{ ") != std::string::npos);
    CHECK(body.find("ys-4(r1)") != std::string::npos);
    CHECK(verify(m, r) == std::nullopt); // every short trip, every exit
}

TEST_CASE("with a branch bubble .trip repeats the kernel, each copy with its exit test, paying the bubble once per "
          "pass of the whole kernel", "[unit][sched][trip]") {
    const isa::Machine m = isa::load_machine("os-real");
    REQUIRE(m.branch_penalty > 0);
    // A reduction (bench/corpus/dot.sa): 2 register copies, the bubble paid every 6 cycles without repeats.
    const std::string loop = R"(        .data 0x1000
xs:     .space 1024
ys:     .space 1024
        .text
        li    r1, 0
        li    r9, 64
        fli   f5, 0.0
        nop
        nop
        .pipeline r9
        .trip 64
        flw   %x, xs(r1)
        flw   %y, ys(r1)
        fmul  %p, %x, %y
        fadd  f5, f5, %p
        addi  r1, r1, 4
        .endpipeline
        halt
)";
    const std::string text = labelled(loop);
    const sched::PipelineResult r = sched::pipeline_source(text, "t.sa", m, {});
    REQUIRE(r.loops[0].trip);
    const sched::TripChoice& c = *r.loops[0].trip;
    INFO(r.report);
    CHECK(r.groups > 1);
    CHECK(c.chosen.groups == r.groups);
    CHECK(c.first.groups == 1);
    CHECK(c.chosen.cycles < c.first.cycles);
    CHECK(r.code.find("        beqz ") != std::string::npos); // an exit test inside the kernel
    CHECK(r.report.find("#   kernel repeated ") != std::string::npos);
    // Every exit (from each repeat, and after the last) at the whole-run cycles the choice is made
    // by: the same code costed at each expected count (`.trip 64, N`) against the ISS's run of N.
    const int copies = r.unroll * r.groups;
    int same_code = 0;
    for (int n = 64; n <= 64 + copies + r.unroll; ++n) {
        INFO("trip " << n);
        std::string at_n = text;
        at_n.replace(at_n.find(".trip 64"), 8, fmt::format(".trip 64, {}", n));
        const sched::PipelineResult at = sched::pipeline_source(at_n, "t.sa", m, {});
        if (at.code != r.code) continue;
        ++same_code;
        const std::string run = sched::with_trip(r, m, static_cast<std::uint32_t>(n)).pipelined;
        CHECK(static_cast<std::int64_t>(region_cycles(run, m)) == at.loops[0].trip->chosen.cycles);
    }
    CHECK(same_code > copies);
    CHECK(verify(m, r) == std::nullopt);
    const std::vector<std::uint32_t> trips = sched::verification_trips(r);
    CHECK(trips.size() >= static_cast<std::size_t>(copies + r.unroll + 1)); // every exit, every remainder
}
