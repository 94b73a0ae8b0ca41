// Nop insertion for hand-scheduled code on slower machines (sched/legalize.hpp): the result is
// accepted by the assembler and computes what the code computes on the machine it was written for.
#include "sched/legalize.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"

#include "base/error.hpp"

#include <catch2/catch.hpp>

#include <optional>
#include <string>

using namespace nesshi;

namespace {

std::function<std::optional<std::string>(const std::string&)> assembles(const isa::Machine& m) {
    return [&m](const std::string& t) -> std::optional<std::string> {
        const assembler::AsmResult r = assembler::assemble_string(t, "k.s", m, {});
        if (r.ok) return std::nullopt;
        return r.diagnostics;
    };
}

// r5 after running `text` on `m`.
std::uint32_t result(const std::string& text, const isa::Machine& m) {
    const assembler::AsmResult r = assembler::assemble_string(text, "k.s", m, {});
    REQUIRE(r.ok);
    iss::Processor p(iss::load_program(r.object, m));
    REQUIRE(p.run(10000) == iss::Status::Halted);
    return p.reg(5); // the integer file comes first in the flat numbering
}

// Written for os (results land a cycle after issue): a multiply read at once, a loop whose body
// reads the multiply of the previous pass around the back edge, and a read of the old r7 in the
// bundle that overwrites it.
const char* kCode = R"(        li r1, 3
        li r2, 7
        li r5, 0
        li r7, 100
        { add r8, r7, r0 ; li r7, 1 }
        mul r3, r1, r2
        { add r5, r5, r3 ; addi r4, r0, 4 }
loop:   { add r5, r5, r3 ; addi r4, r4, -1 }
        { mul r3, r3, r1 ; bnez r4, loop }
        add r5, r5, r8
        add r5, r5, r7
        halt
)";

} // namespace

TEST_CASE("legalize: nops where a value is still in flight, the result the ideal machine computes", "[unit][sched]") {
    const isa::Machine os = isa::load_machine("os"), real = isa::load_machine("os-real");
    REQUIRE(!assembles(os)(kCode)); // legal as written for os
    REQUIRE(assembles(real)(kCode)); // not for os-real: mul takes 3 cycles there
    const sched::Legalized l = sched::legalize(kCode, "k.s", assembles(real));
    CHECK(!assembles(real)(l.text));
    CHECK(l.nops == 3); // two before the first add, one at the loop head (the taken-branch bubble is the other)
    CHECK(!l.where.empty());
    CHECK(l.text.find("loop:\n") != std::string::npos); // the label stays before its nops
    CHECK(result(l.text, real) == result(kCode, os));
    // Nothing to do on the machine it was written for.
    CHECK(sched::legalize(kCode, "k.s", assembles(os)).nops == 0);
}

TEST_CASE("legalize: an error nops cannot fix is reported as it is", "[unit][sched]") {
    const isa::Machine real = isa::load_machine("os-real");
    CHECK_THROWS_WITH(sched::legalize("        frob r1\n        halt\n", "k.s", assembles(real)),
                      Catch::Contains("k.s:1:9: error"));
}

TEST_CASE("legalize: a write that would land before an earlier one waits until it lands after", "[unit][sched]") {
    // On os the mul lands first and the li over it; on os-real the mul takes 3 cycles and the li,
    // one bundle later, would land first and the mul's older value over it.
    const char* code = "        li r1, 3\n        li r2, 7\n        mul r5, r1, r2\n        li r5, 9\n        halt\n";
    const isa::Machine os = isa::load_machine("os"), real = isa::load_machine("os-real");
    REQUIRE(!assembles(os)(code));
    const std::optional<std::string> diags = assembles(real)(code);
    REQUIRE(diags);
    CHECK(diags->find("k.s:4:9: error: r5 is written before an earlier write to it lands") != std::string::npos);
    const sched::Legalized l = sched::legalize(code, "k.s", assembles(real));
    CHECK(!assembles(real)(l.text));
    CHECK(l.nops == int(real.latency[int(isa::OpClass::Mul)]) - 1); // lands one cycle after the mul
    CHECK(result(l.text, real) == 9);
    CHECK(result(l.text, real) == result(code, os));
}

TEST_CASE("legalize: a bundle beyond the machine's ports gives an op a bundle of its own", "[unit][sched]") {
    // Found by the random-machine test: the OS kernel's hand bundles write two float registers
    // at once ({ beq ; fsel ; fmin }); an OS with one FPRF write port refused the kernel.
    isa::Machine one = isa::load_machine("os");
    one.name = "os-1w";
    one.regs[static_cast<std::size_t>(isa::RegFile::Int)].write_ports = 1;
    one.regs[static_cast<std::size_t>(isa::RegFile::Float)].write_ports = 1;
    const char* code = "        li r1, 3\n        li r2, 4\n        fli f1, 1.5\n"
                       "here:   { add r3, r1, r2 ; mul r4, r1, r2 ; fadd f3, f1, f1 ; fmul f4, f1, f1 }\n"
                       "        sub r5, r4, r3\n        fsub f5, f4, f3\n        ftoi r6, f5\n        add r5, r5, r6\n        halt\n";
    REQUIRE(assembles(one)(code));
    const sched::Legalized l = sched::legalize(code, "k.s", assembles(one));
    INFO(l.text);
    CHECK(!assembles(one)(l.text));
    CHECK(l.splits == 2);
    CHECK(l.text.find("here:   { ") == l.text.find("here:")); // the label stays first, on a moved op
    CHECK(result(l.text, one) == result(code, isa::load_machine("os")));
    // An op whose destination its bundle also reads cannot move: the other would see the new value.
    const char* reads = "        li r1, 3\n        li r2, 4\n        { add r3, r1, r2 ; add r1, r2, r2 }\n        halt\n";
    REQUIRE(assembles(one)(reads));
    CHECK_THROWS_WITH(sched::legalize(reads, "k.s", assembles(one)), Catch::Contains("write ports"));
}
