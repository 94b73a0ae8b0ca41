// iss/memory_dump.hpp: dump specs, dumps by label, expected-value files and the comparison.
#include "assembler/assembler.hpp"
#include "iss/memory_dump.hpp"
#include "iss/program.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <stdexcept>

using namespace nesshi;
using namespace nesshi::iss;

namespace {
const char* kProgram = R"(# machine: os
        .data 0x1000
xs:     .float 1.0, 2.0, 3.0
ys:     .word 7, -1
        .text
        { li r1, xs ; fli f1, 0.5 }
        flw f2, 4(r1)
        fadd f3, f2, f1
        fsw f3, 8(r1)
        halt
)";
std::shared_ptr<const Program> program() {
    const isa::Machine m = isa::load_machine("os");
    const assembler::AsmResult r = assembler::assemble_string(kProgram, "dump.s", m, {});
    REQUIRE(r.ok);
    return load_program(r.object, m);
}
} // namespace

TEST_CASE("parse_dump_spec: label, count, format in that order", "[unit][iss][dump]") {
    CHECK(parse_dump_spec("ys").label == "ys");
    CHECK(!parse_dump_spec("ys").count);
    CHECK(parse_dump_spec("ys").format == DumpFormat::f32);
    CHECK(*parse_dump_spec("ys:8").count == 8);
    CHECK(parse_dump_spec("ys:hex").format == DumpFormat::hex);
    const DumpSpec d = parse_dump_spec("ys:3:i32");
    CHECK((*d.count == 3 && d.format == DumpFormat::i32));
    CHECK_THROWS_WITH(parse_dump_spec("ys:0"), Catch::Contains("at least 1"));
    CHECK_THROWS_WITH(parse_dump_spec("ys:f64"), Catch::Contains("neither a word count nor a format"));
    CHECK_THROWS_WITH(parse_dump_spec("ys:hex:3"), Catch::Contains("neither"));
    CHECK_THROWS(parse_dump_spec(":3"));
    CHECK_THROWS(parse_dump_spec("a:1:f32:x"));
}

TEST_CASE("dump_memory reads a data label after the run, up to the next label by default", "[unit][iss][dump]") {
    Processor p(program());
    REQUIRE(p.run(1000) == Status::Halted);
    const MemoryDump xs = dump_memory(p, parse_dump_spec("xs"));
    REQUIRE(xs.words.size() == 3);
    CHECK(std::bit_cast<float>(xs.words[2]) == 2.5f); // the program stored 2.0 + 0.5
    CHECK(xs.text() == "xs @ 0x00001000: 3 x f32\n  [0] 1 2 2.5\n");
    const MemoryDump ys = dump_memory(p, parse_dump_spec("ys:i32"));
    CHECK(ys.text() == "ys @ 0x0000100c: 2 x i32\n  [0] 7 -1\n");
    CHECK(dump_memory(p, parse_dump_spec("ys:1:hex")).text() == "ys @ 0x0000100c: 1 x hex\n  [0] 0x00000007\n");
    CHECK_THROWS_WITH(dump_memory(p, parse_dump_spec("zs")), Catch::Contains("no label 'zs'"));
    CHECK_THROWS_WITH(dump_memory(p, parse_dump_spec("ys:1000000")), Catch::Contains("outside the memories"));
}

TEST_CASE("compare: the first difference, with both values and the ulp distance", "[unit][iss][dump]") {
    Processor p(program());
    REQUIRE(p.run(1000) == Status::Halted);
    const MemoryDump xs = dump_memory(p, parse_dump_spec("xs"));
    CHECK(!compare(xs, parse_values("1 2 2.5", "x.txt", DumpFormat::f32), 0));
    const Mismatch m = compare(xs, parse_values("1, 2, # third:\n 2.5000002", "x.txt", DumpFormat::f32), 0);
    REQUIRE(m);
    CHECK(m.index == 2);
    CHECK(m.message == "xs[2] (0x00001008): expected 2.5000002 (0x40200001), got 2.5 (0x40200000): 1 ulp apart");
    CHECK(!compare(xs, parse_values("1 2 2.5000002", "x.txt", DumpFormat::f32), 1));
    CHECK(compare(xs, parse_values("1 2", "x.txt", DumpFormat::f32), 0).message == "xs: the file holds 2 values, the dump 3 words");
    const MemoryDump ys = dump_memory(p, parse_dump_spec("ys:i32"));
    CHECK(!compare(ys, parse_values("7 0xffffffff", "y.txt", DumpFormat::i32), 0));
    CHECK_THROWS_WITH(parse_values("7\n1.5", "y.txt", DumpFormat::i32), "y.txt:2: error: '1.5' is not an integer value");
    CHECK_THROWS_WITH(parse_values("x", "f.txt", DumpFormat::f32), "f.txt:1: error: 'x' is not a float value");
}

TEST_CASE("ulp_distance counts representable floats between two patterns", "[unit][iss][dump]") {
    CHECK(ulp_distance(0x3f800000u, 0x3f800000u) == 0);
    CHECK(ulp_distance(0x3f800000u, 0x3f800001u) == 1);
    CHECK(ulp_distance(0x00000000u, 0x80000000u) == 1); // +0 and -0
    CHECK(ulp_distance(0x00000001u, 0x80000001u) == 3);
}
