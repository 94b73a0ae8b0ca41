// Self-tests of the operation table: every row is complete and consistent.
#include "isa/ops.hpp"
#include "isa/printer.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace nesshi::isa;

TEST_CASE("every operation has a mnemonic, semantics, a class and a summary") {
    std::set<std::string_view> names;
    for (const auto& op : kOps) {
        INFO(op.mnemonic);
        CHECK(!op.mnemonic.empty());
        CHECK(op.eval != nullptr);
        CHECK(!op.summary.empty());
        CHECK(names.insert(op.mnemonic).second);
        CHECK(int(op.cls) < kNumOpClasses);
    }
    CHECK(kNumOps <= 128);
}

TEST_CASE("the basic RISC mnemonics the project promises exist") {
    for (auto m : {"add", "sub", "mul", "and", "or", "xor", "sll", "srl", "sra", "addi", "slt",
                   "lw", "sw", "flw", "fsw", "fadd", "fsub", "fmul", "fdiv", "fsqrt", "fmin",
                   "fmax", "fabs", "fneg", "flt", "fle", "feq", "mov", "fmov", "itof", "ftoi",
                   "beq", "bne", "jmp", "recv", "send", "nop", "halt", "sel", "fsel"})
        CHECK(find_opcode(m).has_value());
}

TEST_CASE("no operation fuses two arithmetic steps") {
    // Honest operations: each row reads at most three registers and writes at most one.
    for (const auto& op : kOps) {
        PortUse p = port_use(op);
        CHECK(p.reads[0] + p.reads[1] <= 3);
        CHECK(p.writes[0] + p.writes[1] <= 1);
    }
}

TEST_CASE("port use counts loads, compares, selects and FIFO receives") {
    CHECK(port_use(kOps[opcode("flw")]).reads[0] == 1);
    CHECK(port_use(kOps[opcode("flw")]).writes[1] == 1);
    CHECK(port_use(kOps[opcode("flt")]).reads[1] == 2);
    CHECK(port_use(kOps[opcode("flt")]).writes[0] == 1);
    CHECK(port_use(kOps[opcode("fsel")]).reads[0] == 1);
    CHECK(port_use(kOps[opcode("fsel")]).reads[1] == 2);
    CHECK(port_use(kOps[opcode("frecv")]).writes[1] == 1);
    CHECK(port_use(kOps[opcode("fsw")]).reads[0] == 1);
    CHECK(port_use(kOps[opcode("fsw")]).reads[1] == 1);
}

TEST_CASE("semantics of a few operations on edge values") {
    auto ev = [](std::string_view m, uint32_t a, uint32_t b = 0, uint32_t c = 0, uint32_t i = 0) {
        return kOps[*find_opcode(m)].eval(a, b, c, i);
    };
    auto fb = [](float x) { return std::bit_cast<uint32_t>(x); };
    CHECK(ev("add", 0xffffffffu, 1) == 0);
    CHECK(ev("sra", 0x80000000u, 31) == 0xffffffffu);
    CHECK(ev("srl", 0x80000000u, 31) == 1);
    CHECK(ev("sll", 1, 33) == 2);
    CHECK(ev("slt", 0xffffffffu, 0) == 1);
    CHECK(ev("sltu", 0xffffffffu, 0) == 0);
    CHECK(ev("fadd", fb(1.5f), fb(2.25f)) == fb(3.75f));
    CHECK(ev("fmin", fb(std::nanf("")), fb(2.0f)) == fb(2.0f));
    CHECK(ev("fmin", fb(2.0f), fb(std::nanf(""))) == fb(std::nanf("")));
    CHECK(ev("fneg", fb(0.0f)) == fb(-0.0f));
    CHECK(ev("ftoi", fb(-2.7f)) == uint32_t(-2));
    CHECK(ev("ftoi", fb(3e9f)) == 0x7fffffffu);
    CHECK(ev("ftoi", fb(-3e9f)) == 0x80000000u);
    CHECK(ev("ftoi", fb(std::nanf(""))) == 0);
    CHECK(ev("flt", fb(std::nanf("")), fb(1.0f)) == 0);
    CHECK(ev("fle", fb(-0.0f), fb(0.0f)) == 1);
    CHECK(ev("fsqrt", fb(-1.0f)) != fb(-1.0f)); // NaN
    CHECK(ev("sel", 7, 1, 2) == 1);
    CHECK(ev("sel", 0, 1, 2) == 2);
    // Subnormals are kept.
    float tiny = std::numeric_limits<float>::denorm_min();
    CHECK(ev("fadd", fb(tiny), fb(tiny)) == fb(2 * tiny));
}

TEST_CASE("float immediates print so they read back bit-exactly") {
    CHECK(format_float_bits(std::bit_cast<uint32_t>(1.0f)) == "1.0");
    CHECK(format_float_bits(std::bit_cast<uint32_t>(0.1f)) == "0.1");
    CHECK(format_float_bits(0x7fc00001u) == "0x7fc00001");
    CHECK(format_float_bits(0xff800000u) == "0xff800000");
    CHECK(format_float_bits(std::bit_cast<uint32_t>(-0.0f)) == "-0.0");
}
