// Random-text fuzz of the assembler (fixed seeds): mutated examples and random token soup.
// No crash, errors always rendered with a location, and whatever assembles round-trips.
#include "support.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace nesshi;

namespace {

const std::vector<std::string> kVocabulary = {
    "add", "fadd", "fdiv", "lw", "flw", "fsw", "sel", "fli", "beqz", "jmp", "jal", "jr", "recv", "send", "halt", "nop",
    "r0", "r1", "r127", "r128", "f3", "f200", "iu0:", "fpu1:", "xx:", "{", "}", ";", ",", "(", ")", "+", "-", "*",
    "/", "%", "<<", ">>", "~", "0", "1", "-1", "0x7fffffff", "0xffffffffff", "1.5", "-0.0", "1e40", "'a'", "'",
    "\"", "#", "//", ".data", ".text", ".word", ".byte", ".half", ".float", ".space", ".align", ".equ", ".global",
    ".file", ".loc", ".include", "label", "label:", "\n", "\n", "\n", "\t", " ", "99999999999999999999", "0b",
};

void check_result(const assembler::AsmResult& r, const isa::Machine& m) {
    if (!r.ok) {
        REQUIRE(r.errors > 0);
        REQUIRE(r.diagnostics.find("error") != std::string::npos);
        return;
    }
    std::string dis = assembler::disassemble(r.object, m);
    auto b = assembler::assemble_string(dis, "dis.s", m, {});
    INFO(dis << b.diagnostics);
    REQUIRE(b.ok);
    REQUIRE(isa::write_object(b.object) == isa::write_object(r.object));
}

} // namespace

TEST_CASE("fuzz: mutated example programs", "[fuzz]") {
    auto programs = test::asm_programs();
    REQUIRE_FALSE(programs.empty());
    std::mt19937 rng(20260422);
    int cases = 0;
    for (int round = 0; round < 2000; ++round) {
        const auto& p = programs[rng() % programs.size()];
        std::string text = test::read_text(p);
        isa::Machine m = isa::load_machine(test::header_machine(text));
        int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits && !text.empty(); ++e) {
            size_t at = rng() % text.size();
            switch (rng() % 5) {
            case 0: text.erase(at, 1 + rng() % 6); break;
            case 1: text.insert(at, kVocabulary[rng() % kVocabulary.size()]); break;
            case 2: text.insert(at, 1, char(32 + rng() % 95)); break;
            case 3: { // duplicate a line
                size_t s = text.rfind('\n', at), t = text.find('\n', at);
                s = s == std::string::npos ? 0 : s + 1;
                if (t != std::string::npos) text.insert(s, text.substr(s, t - s + 1));
                break;
            }
            default: text[at] = char(rng() % 256); break;
            }
        }
        // Named after the original so .include still finds its neighbours.
        auto r = assembler::assemble_string(text, p.string(), m, {});
        INFO(text << "\n" << r.diagnostics);
        check_result(r, m);
        ++cases;
    }
    CHECK(cases == 2000);
}

TEST_CASE("fuzz: random token soup", "[fuzz]") {
    std::mt19937 rng(7);
    const isa::Machine machines[] = {isa::load_machine("os"), isa::load_machine("ic"), isa::load_machine("seq")};
    for (int round = 0; round < 2000; ++round) {
        std::string text;
        int n = 1 + int(rng() % 40);
        for (int i = 0; i < n; ++i) {
            text += kVocabulary[rng() % kVocabulary.size()];
            text += rng() % 3 ? " " : "";
        }
        const isa::Machine& m = machines[rng() % 3];
        auto r = assembler::assemble_string(text, "soup.s", m, {});
        INFO(text << "\n" << r.diagnostics);
        check_result(r, m);
    }
}
