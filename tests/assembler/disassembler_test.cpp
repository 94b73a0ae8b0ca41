// The disassembler: labels, data, line table, and clean rejection of foreign objects.
#include "support.hpp"

#include <catch2/catch.hpp>

using namespace nesshi;

namespace {
void require_round_trip(const std::string& src, const std::string& machine = "os") {
    isa::Machine m = isa::load_machine(machine);
    auto a = assembler::assemble_string(src, "t.s", m, {});
    INFO(a.diagnostics);
    REQUIRE(a.ok);
    std::string dis = assembler::disassemble(a.object, m);
    auto b = assembler::assemble_string(dis, "d.s", m, {});
    INFO(dis << b.diagnostics);
    REQUIRE(b.ok);
    CHECK(isa::write_object(a.object) == isa::write_object(b.object));
}
} // namespace

TEST_CASE("disassembly prints labels, slots, braces, data and the line table", "[dis]") {
    isa::Machine m = isa::load_machine("os");
    auto a = assembler::assemble_string(".global top\ntop: { fadd f1, f2, f3 ; add r1, r2, r3 }\nbnez r1, top\n"
                                        "halt\n.data 0x40\nw: .word 5\nb: .byte 1, 2\n", "t.s", m, {});
    REQUIRE(a.ok);
    std::string d = assembler::disassemble(a.object, m);
    CHECK(d.find(".global top\n") != std::string::npos);
    CHECK(d.find("top:\n    {\n        iu0: add r1, r2, r3\n        fpu0: fadd f1, f2, f3\n    }\n") != std::string::npos);
    CHECK(d.find("iu0: bnez r1, top\n") != std::string::npos);
    CHECK(d.find(".file \"t.s\"\n.loc 2\n") != std::string::npos);
    CHECK(d.find(".data 0x00000040\nw:\n    .word 0x00000005\nb:\n    .byte 0x01, 0x02\n") != std::string::npos);
}

TEST_CASE("awkward layouts survive the round trip", "[dis]") {
    require_round_trip("nop\nhalt\nend1:\nend2:\n");
    require_round_trip(".data 0x101\nodd: .byte 1\n.word 0x11223344\nmid: .half 9\n.data 0x800\nempty:\n.text\nhalt\n");
    require_round_trip(".data 0x10\na: .word 1\nb:\n.data 0x14\nc: .word 2\n.text\nhalt\n");
    require_round_trip("jmp 1\nhalt\n");                                        // numeric target
    require_round_trip("x: y: beqz r1, y\nhalt\n");                             // two labels, first name wins
    require_round_trip(".file \"a.c\"\n.loc 3\nnop\n.file \"b.c\"\n.loc 9\nhalt\n.file \"a.c\"\nhalt\n");
    require_round_trip("{ fli f1, -0.0 ; fli f2, 0x7f800001 ; li r1, -1 ; send 4000000000, r2 }\nhalt\n");
    require_round_trip("u0: fadd f1, f2, f3\nhalt\n", "seq");
}

TEST_CASE("objects for another machine are rejected", "[dis]") {
    auto a = test::assemble("halt\n", "os");
    REQUIRE(a.ok);
    CHECK_THROWS_WITH(assembler::disassemble(a.object, isa::load_machine("ic")),
                      Catch::Contains("assembled for machine 'os'"));
    isa::ObjectFile bad = a.object;
    bad.code[0] = 0x7f00000000000000ull | isa::kEndOfBundle; // opcode 127 does not exist
    CHECK_THROWS_AS(assembler::disassemble(bad, isa::load_machine("os")), isa::ObjectError);
}

// Found by fuzz target `object`: a symbol name with a byte no label can hold was printed as is,
// and the text did not re-assemble; a file name with a quote broke its `.file` line.
TEST_CASE("symbol names that are not identifiers are rejected, file names are quoted", "[dis]") {
    const isa::Machine m = isa::load_machine("os");
    auto a = test::assemble("start: halt\n", "os");
    REQUIRE(a.ok);
    for (const char* name : {"resu\xb1t", "2x", "a b", "x\n"}) {
        isa::ObjectFile bad = a.object;
        bad.symbols[0].name = name;
        CHECK_THROWS_WITH(assembler::disassemble(bad, m), Catch::Contains("not an identifier"));
    }
    for (const char* name : {"fpu1", "r7", "f0"}) { // read as a slot prefix or refused as a label
        isa::ObjectFile bad = a.object;
        bad.symbols[0].name = name;
        CHECK_THROWS_WITH(assembler::disassemble(bad, m), Catch::Contains("name of a register or issue slot"));
    }
    isa::ObjectFile twice = a.object; // found later by the same target
    twice.symbols.push_back(twice.symbols[0]);
    CHECK_THROWS_WITH(assembler::disassemble(twice, m), Catch::Contains("symbol 'start' is defined twice"));
    isa::ObjectFile odd = a.object;
    odd.files = {"we\"ird\\dir\n\tname.s"};
    odd.lines = {{0, 3}};
    const std::string dis = assembler::disassemble(odd, m);
    auto b = assembler::assemble_string(dis, "d.s", m, {});
    INFO(dis << b.diagnostics);
    REQUIRE(b.ok);
    CHECK(b.object.files == odd.files);
}

// Found by fuzz target `object`: a branch to a bundle past the code disassembled into a source the
// assembler rejects ("branch target ... is outside the code").
TEST_CASE("a branch target outside the code is rejected", "[dis]") {
    auto a = test::assemble("top: jmp top\nhalt\n", "os");
    REQUIRE(a.ok);
    isa::ObjectFile bad = a.object;
    auto bundles = isa::decode_bundles(bad);
    isa::Instr jmp = bundles[0][0];
    jmp.imm = 2; // two bundles: 0..1
    bad.code[0] = isa::encode(jmp, true);
    CHECK_THROWS_WITH(assembler::disassemble(bad, isa::load_machine("os")),
                      Catch::Contains("branch target 2 is outside the code (bundles 0..1)"));
}
