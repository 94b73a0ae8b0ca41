// Assembler behaviour: syntax, directives, symbols, object layout and diagnostics shape.
#include "support.hpp"

#include "isa/printer.hpp"

#include <catch2/catch.hpp>

#include <bit>

using namespace nesshi;
using test::assemble;

TEST_CASE("the port-conflict bundle fails on os with a caret at flw and passes on ic", "[diag]") {
    const std::string src = "{ fadd f1, f2, f3 ; fadd f4, f5, f6 ; flw f7, 0(r1) }\nhalt\n";
    auto os = assemble(src, "os");
    CHECK_FALSE(os.ok);
    CHECK(os.errors == 1);
    CHECK(os.diagnostics ==
          "test.s:1:39: error: bundle needs more than 2 FPRF write ports in cycle +1; os has 2\n"
          "{ fadd f1, f2, f3 ; fadd f4, f5, f6 ; flw f7, 0(r1) }\n"
          "                                      ^\n"
          "test.s:1:3: note: first FPRF write landing in cycle +1\n"
          "{ fadd f1, f2, f3 ; fadd f4, f5, f6 ; flw f7, 0(r1) }\n"
          "  ^\n"
          "1 error generated.\n");
    auto ic = assemble(src, "ic");
    CHECK(ic.ok);
    CHECK(ic.diagnostics.empty());
    CHECK(ic.object.code.size() == 4);
}

TEST_CASE("every error of a file is reported in one run", "[diag]") {
    auto r = assemble("bogus r1\nadd r1, r2\nbeqz r1, nowhere\n{ lw r1, 0(r2) ; lw r3, 0(r2) ; lw r4, 0(r2) }\nhalt\n");
    CHECK_FALSE(r.ok);
    CHECK(r.errors >= 4);
    CHECK(r.diagnostics.find("test.s:1:1: error: unknown operation 'bogus'") != std::string::npos);
    CHECK(r.diagnostics.find("test.s:2:1: error: 'add' takes 3 operands") != std::string::npos);
    CHECK(r.diagnostics.find("test.s:3:10: error: undefined symbol 'nowhere'") != std::string::npos);
    CHECK(r.diagnostics.find("test.s:4:33: error: no free issue slot for 'lw'") != std::string::npos);
}

TEST_CASE("carets keep tabs so they line up", "[diag]") {
    auto r = assemble("\tadd r1, r2\n\thalt\n");
    CHECK(r.diagnostics.find("\tadd r1, r2\n\t^\n") != std::string::npos);
}

TEST_CASE("bundles: one line, several lines, pinned slots, canonical slot order", "[syntax]") {
    auto r = assemble("top: { fadd f1, f2, f3 ; add r1, r2, r3 }\n{\n  fpu1: fmul f4, f5, f6\n  iu1: sub r4, r5, r6 // c\n}\n"
                      "fpu0: nop # alone\nhalt\n");
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    auto bundles = isa::decode_bundles(r.object);
    REQUIRE(bundles.size() == 4);
    REQUIRE(bundles[0].size() == 2);
    CHECK(bundles[0][0].info().mnemonic == "add"); // slot order, not source order
    CHECK(bundles[0][0].slot == 0);
    CHECK(bundles[0][1].slot == 2);
    CHECK(bundles[1][0].slot == 1);
    CHECK(bundles[1][1].slot == 3);
    CHECK(bundles[2][0].slot == 2);
    CHECK((r.object.code[1] & isa::kEndOfBundle) != 0);
    CHECK((r.object.code[0] & isa::kEndOfBundle) == 0);
    REQUIRE(r.object.lines.size() == 4);
    CHECK(r.object.lines[1].line == 2);
    CHECK(r.object.files == std::vector<std::string>{"test.s"});
}

TEST_CASE("labels, data, expressions and symbols", "[syntax]") {
    auto r = assemble(R"(
        .equ COUNT, end - start      # forward reference
        .global start, table
start:  li r1, table + 4 * 2
        li r2, COUNT
        { li r3, 'A' ; li r4, -(1 << 31) }
        fli f1, -2.5
        fli f2, 0x7fc00000
end:    halt
        .data 0x100
table:  .word 1, -1, 0xdeadbeef
        .half 0x1234
        .byte 7
        .align 4
        .float 1.5, 0x3f800000
        .space 3
tail:
)");
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    auto b = isa::decode_bundles(r.object);
    CHECK(b[0][0].imm == 0x108);
    CHECK(b[1][0].imm == 5);
    for (const auto& in : b[2]) CHECK(in.imm == (in.rd == 3 ? uint32_t('A') : 0x80000000u));
    CHECK(b[3][0].imm == std::bit_cast<uint32_t>(-2.5f));
    CHECK(b[4][0].imm == 0x7fc00000u);
    REQUIRE(r.object.data.size() == 1);
    const auto& d = r.object.data[0];
    CHECK(d.address == 0x100);
    CHECK(d.bytes.size() == 12 + 2 + 1 + 1 + 8 + 3);
    CHECK(d.bytes[4] == 0xff);
    CHECK(d.bytes[8] == 0xef);
    CHECK(d.bytes[12] == 0x34);
    CHECK(d.bytes[14] == 7);
    CHECK(d.bytes[15] == 0);
    CHECK(d.bytes[19] == 0x3f);
    std::vector<isa::Symbol> want = {{"start", isa::SymbolKind::Code, 0, true},
                                     {"end", isa::SymbolKind::Code, 5, false},
                                     {"table", isa::SymbolKind::Data, 0x100, true},
                                     {"tail", isa::SymbolKind::Data, 0x100 + 27, false}};
    CHECK(r.object.symbols == want);
    CHECK(r.object.machine == "os");
    CHECK(r.object.machine_fingerprint == isa::load_machine("os").fingerprint());
}

TEST_CASE(".file and .loc set the line table", "[syntax]") {
    auto r = assemble(".file \"orig.c\"\n.loc 40\nnop\nnop\n.loc 7\nhalt\n");
    REQUIRE(r.ok);
    CHECK(r.object.files == std::vector<std::string>{"orig.c"});
    REQUIRE(r.object.lines.size() == 3);
    CHECK(r.object.lines[0].line == 40);
    CHECK(r.object.lines[1].line == 4);
    CHECK(r.object.lines[2].line == 7);
}

TEST_CASE(".include finds files beside the source and in -I directories", "[syntax]") {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / "nesshi_asm_include_test";
    fs::create_directories(dir / "inc");
    std::ofstream(dir / "inc" / "consts.s") << ".equ SEVEN, 7\n";
    std::ofstream(dir / "main.s") << ".include \"consts.s\"\nli r1, SEVEN\nhalt\n";
    std::ofstream(dir / "self.s") << ".include \"self.s\"\n";
    assembler::AsmOptions opts;
    auto miss = assembler::assemble_file((dir / "main.s").string(), isa::load_machine("os"), opts);
    CHECK_FALSE(miss.ok);
    CHECK(miss.diagnostics.find("cannot find include file \"consts.s\"") != std::string::npos);
    opts.include_dirs.push_back((dir / "inc").string());
    auto ok = assembler::assemble_file((dir / "main.s").string(), isa::load_machine("os"), opts);
    INFO(ok.diagnostics);
    CHECK(ok.ok);
    auto loop = assembler::assemble_file((dir / "self.s").string(), isa::load_machine("os"), opts);
    CHECK_FALSE(loop.ok);
    CHECK(loop.diagnostics.find("nested more than") != std::string::npos);
    auto none = assembler::assemble_file((dir / "missing.s").string(), isa::load_machine("os"), opts);
    CHECK_FALSE(none.ok);
    CHECK(none.diagnostics.find("cannot open") != std::string::npos);
}

TEST_CASE("ranges and misuse are diagnosed", "[diag]") {
    struct Case { const char* src; const char* message; };
    const Case cases[] = {
        {"li r1, 0x1_0\nhalt\n", "malformed number"},
        {"addi r1, r2, 1 / 0\nhalt\n", "division by zero"},
        {"li r1, 1 << 64\nhalt\n", "shift amount out of range"},
        {"fli f1, 1e39\nhalt\n", "out of range for binary32"},
        {"lw r1, 4(f2)\nhalt\n", "expects an integer register"},
        {".data 0x10\n.word 1\n.data 0x12\n.word 2\n.text\nhalt\n", "overlaps earlier data"},
        {".word 5\nhalt\n", "data directive outside .data"},
        {".data\nadd r1, r2, r3\n", "operation in a .data section"},
        {".data\n.align 3\n", "power of two"},
        {".equ X, 1\n.equ X, 2\nhalt\n", "already defined"},
        {".global nothing\nhalt\n", "undefined label 'nothing'"},
        {".bogus\nhalt\n", "unknown directive"},
        {"{ }\nhalt\n", "empty bundle"},
        {"}\nhalt\n", "without a matching"},
        {"r1: halt\n", "register name"},
        {"send -1, r1\nhalt\n", "channel -1 out of range"},
        {".data 0x100\n.space x\nx:\n", "'x' is undefined here"},
        {".equ N, x\n.data 0x100\n.space N\nx:\n", "'x' is undefined here"},
        {"li r1, \"s\"\nhalt\n", "expects an immediate"},
        {"add r1, r2, r3 @\n", "unexpected character '@'"},
        {".data 0xfffffff0\n.space 32\n.text\nhalt\n", "past the end of the 32-bit address space"},
        {".data 0\n.space 0x4000000\n.space 0x4000000\n.space 0x4000000\n.space 0x4000000\n.space 1\n", "larger than"},
    };
    for (const auto& c : cases) {
        auto r = assemble(c.src);
        INFO(c.src << "\n" << r.diagnostics);
        CHECK_FALSE(r.ok);
        CHECK(r.diagnostics.find(c.message) != std::string::npos);
    }
}

TEST_CASE("registers are checked against a machine's register-file sizes", "[diag]") {
    std::string toml(isa::preset_text("os"));
    auto pos = toml.find("count = 128");
    REQUIRE(pos != std::string::npos);
    toml.replace(pos, 11, "count = 32");
    isa::Machine small = isa::parse_machine(toml, "small.toml");
    auto r = assembler::assemble_string("addi r40, r1, 1\naddi r31, r1, 1\nhalt\n", "t.s", small, {});
    CHECK(r.errors == 1);
    CHECK(r.diagnostics.find("register r40 out of range: os has r0..r31") != std::string::npos);
}

TEST_CASE("the listing shows encodings, slots, source and port usage", "[listing]") {
    assembler::AsmOptions opts;
    opts.listing = true;
    auto r = assembler::assemble_string("loop: { fadd f1, f2, f3 ; add r1, r2, r3 }\nhalt\n", "t.s",
                                        isa::load_machine("os"), opts);
    REQUIRE(r.ok);
    CHECK(r.listing.find("loop:\n") != std::string::npos);
    CHECK(r.listing.find(fmt::format("{:016x}", r.object.code[0])) != std::string::npos);
    CHECK(r.listing.find("fpu0   fadd f1, f2, f3") != std::string::npos);
    CHECK(r.listing.find("ports IRF r2/5 w1/2  FPRF r2/5 w1/2   units 2/4 (iu0 fpu0)") != std::string::npos);
}

// A chain of ~10,300 `.equ eN, eN+1` overflowed the stack (each link recursed through the
// evaluator, and the depth guard was per expression): chains share one nesting limit, and the
// message names the first links and the reason, not all 10,300.
TEST_CASE("long .equ chains are an error, not a stack overflow", "[diag][equ]") {
    std::string text;
    const int n = 10300;
    for (int k = 0; k < n; ++k) text += ".equ e" + std::to_string(k) + ", e" + std::to_string(k + 1) + "+1\n";
    text += ".equ e" + std::to_string(n) + ", 1\nli r1, e0\nhalt\n";
    const auto r = assemble(text);
    CHECK_FALSE(r.ok);
    CHECK(r.errors == 1);
    CHECK(r.diagnostics.rfind("test.s:10302:8: error: 'e0' has no value: 'e1' has no value: 'e2' has no value: "
                              "'e3' has no value: 'e4' has no value: 'e5' has no value: 'e6' has no value: 'e7' "
                              "has no value: ...: expression nested too deeply\n", 0) == 0);
    // A chain within the limit has its value; one that ends in an unknown name says so, and the
    // message of a long chain stays short.
    std::string ok;
    for (int k = 0; k < 200; ++k) ok += ".equ e" + std::to_string(k) + ", e" + std::to_string(k + 1) + "+1\n";
    const auto good = assemble(ok + ".equ e200, 1\nli r1, e0\nhalt\n");
    INFO(good.diagnostics);
    CHECK(good.ok);
    const auto bad = assemble(ok + "li r1, e0\nhalt\n");
    CHECK(bad.errors == 1);
    CHECK(bad.diagnostics.find("'e7' has no value: ...: undefined symbol 'e200'; did you mean 'e100'?\n") != std::string::npos);
    CHECK(bad.diagnostics.size() < 400);
    const auto two = assemble(".equ a, b\n.equ b, c\nli r1, a\nhalt\n");
    CHECK(two.diagnostics.find("error: 'a' has no value: 'b' has no value: undefined symbol 'c'\n") != std::string::npos);
}

// Forty `.equ aN, aN-1+aN-1` levels feeding .space or .loc took exponential time (28 levels:
// 16 s): values computed where they stand were never kept. A value is now kept with the latest
// definition it needs, so each name is evaluated once.
TEST_CASE(".equ values are evaluated once, also where they stand", "[equ]") {
    std::string text = ".equ a0, 1\n";
    for (int k = 1; k <= 40; ++k)
        text += ".equ a" + std::to_string(k) + ", a" + std::to_string(k - 1) + "+a" + std::to_string(k - 1) + "\n";
    const auto r = assemble(text + ".data 0x100\n.space a40 >> 37\n.text\n.loc a40 >> 30\nhalt\n");
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    REQUIRE(r.object.data.size() == 1);
    CHECK(r.object.data[0].bytes.size() == 8);
    CHECK(r.object.lines.at(0).line == 1024);
    // Where a name is not known yet it is an error there, and known after its definition.
    const auto late = assemble(".equ A, B + 1\n.data 0x100\n.space A\n.equ B, 3\n.space A\n.text\nhalt\n");
    CHECK(late.errors == 1);
    CHECK(late.diagnostics.find("test.s:3:8: error: 'A' has no value: 'B' is undefined here") != std::string::npos);
    const auto known = assemble(".equ B, 3\n.equ A, B + 1\n.data 0x100\n.space A\n.space A\n.text\nli r1, A\nhalt\n");
    INFO(known.diagnostics);
    REQUIRE(known.ok);
    CHECK(known.object.data.at(0).bytes.size() == 8);
}

// One 20 KB line of '}' made 600 MB of diagnostics (every stray token an error, each printing the
// whole line); 60 KB ran out of memory. As clang does, the assembler stops after 20 errors, and
// a line longer than 160 characters is shown cut around the caret.
TEST_CASE("a flood of errors stops at the error limit", "[diag]") {
    const auto r = assemble(std::string(20000, '}') + "\nhalt\n");
    CHECK(r.errors == 20);
    CHECK(r.diagnostics.size() < 5000);
    CHECK(r.diagnostics.ends_with("}...\n                   ^\nfatal error: too many errors emitted, stopping now\n"
                                  "20 errors generated.\n"));
    std::string lines;
    for (int k = 0; k < 25; ++k) lines += "bogus r1\n";
    CHECK(assemble(lines).errors == 20);
    CHECK(assemble(lines.substr(0, 20 * 9)).diagnostics.find("too many errors") == std::string::npos);
    assembler::AsmOptions all;
    all.error_limit = 0;
    CHECK(assembler::assemble_string(lines, "test.s", isa::load_machine("os"), all).errors == 25);
}

TEST_CASE("long source lines are cut around the caret", "[diag]") {
    const std::string before(300, 'x'), after(300, 'y');
    const auto r = assemble("li r1, 1 # " + before + "\n\tadd r1, r2 # " + after + "\n" + "halt\n");
    // The caret near the start: the line's first 160 characters, then "...".
    CHECK(r.diagnostics.find("test.s:2:2: error: 'add' takes 3 operands (rd, rs1, rs2), found 2\n\tadd r1, r2 # " +
                             std::string(146, 'y') + "...\n\t^\n") != std::string::npos);
    // In the middle: 80 characters either side, "..." at both ends, the caret moved by the cut.
    const auto mid = assemble("li r1, " + std::string(200, ' ') + "nowhere" + std::string(200, ' ') + "\nhalt\n");
    const std::string shown = "..." + std::string(80, ' ') + "nowhere" + std::string(73, ' ') + "...\n";
    CHECK(mid.diagnostics == "test.s:1:208: error: undefined symbol 'nowhere'\n" + shown + std::string(83, ' ') +
                                 "^\n1 error generated.\n");
    // A cut never splits a UTF-8 sequence: "é" is two bytes.
    std::string utf8;
    for (int k = 0; k < 150; ++k) utf8 += "\xc3\xa9";
    const auto u = assemble("nowhere r1 # " + utf8 + "\nhalt\n");
    const std::string first = u.diagnostics.substr(u.diagnostics.find('\n') + 1);
    const std::string line = first.substr(0, first.find('\n'));
    CHECK(line.ends_with("\xc3\xa9..."));
    CHECK(line.size() <= 160 + 3);
}

// An empty file used to give an object with no code and no word about it.
TEST_CASE("a source without code assembles with a warning", "[diag]") {
    for (const std::string text : {"", "# only a comment\n", ".data 0x100\n.word 1\n"}) {
        const auto r = assemble(text);
        INFO(text);
        CHECK(r.ok);
        CHECK(r.warnings == 1);
        CHECK(r.diagnostics == "test.s: warning: no code: the object has no bundle to run (end a program with "
                               "'halt')\n1 warning generated.\n");
        CHECK(r.object.code.empty());
    }
    CHECK(assemble("halt\n").diagnostics.empty());
}

TEST_CASE("an unknown operation, directive or symbol one slip from a known one gets a 'did you mean'", "[diag]") {
    CHECK(assemble("fadx f1, f2, f3\nhalt\n").diagnostics.find("unknown operation 'fadx'; did you mean 'fadd'?") != std::string::npos);
    CHECK(assemble(".wrd 3\nhalt\n").diagnostics.find("unknown directive '.wrd'; did you mean '.word'?") != std::string::npos);
    const auto r = assemble("loop: li r1, 3\nbnez r1, lop\nhalt\n");
    CHECK(r.diagnostics.find("undefined symbol 'lop'; did you mean 'loop'?") != std::string::npos);
    // Nothing near: no suggestion.
    CHECK(assemble("zzzz f1, f2, f3\nhalt\n").diagnostics.find("did you mean") == std::string::npos);
}
