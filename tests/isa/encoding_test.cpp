// Encoder/decoder: every operation round-trips; illegal words are rejected with a reason.
#include "isa/encoding.hpp"
#include "isa/printer.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace nesshi::isa;

namespace {
// A random, legal instance of an operation (fields it does not use stay zero).
Instr random_instr(Opcode opc, std::mt19937& rng) {
    Instr in;
    in.opcode = opc;
    in.slot = uint8_t(rng() % kMaxSlots);
    unsigned used = used_fields(kOps[opc]);
    auto r7 = [&] { return uint8_t(rng() % 128); };
    if (used & 1u << int(Field::Rd)) in.rd = r7();
    if (used & 1u << int(Field::Rs1)) in.rs1 = r7();
    if (used & 1u << int(Field::Rs2)) in.rs2 = r7();
    if (used & 1u << int(Field::Rs3)) in.rs3 = r7();
    if (used & 1u << int(Field::Imm)) in.imm = uint32_t(rng());
    return in;
}
} // namespace

TEST_CASE("encode then decode is the identity for every operation") {
    std::mt19937 rng(1);
    for (int opc = 0; opc < kNumOps; ++opc)
        for (int k = 0; k < 200; ++k) {
            Instr in = random_instr(Opcode(opc), rng);
            bool end = k % 2;
            DecodeResult d = decode(encode(in, end));
            INFO(format_instr(in));
            REQUIRE(d.ok);
            CHECK(d.instr == in);
            CHECK(d.end_of_bundle == end);
        }
}

TEST_CASE("distinct operations never share an encoding") {
    std::mt19937 rng(2);
    for (int k = 0; k < 20000; ++k) {
        uint64_t w = (uint64_t(rng()) << 32) | rng();
        DecodeResult d = decode(w);
        if (!d.ok) continue;
        // A word decodes to one operation only: re-encoding gives the same word.
        CHECK(encode(d.instr, d.end_of_bundle) == w);
    }
}

TEST_CASE("illegal words are rejected with a reason") {
    DecodeResult d = decode(uint64_t{127} << 56);
    CHECK_FALSE(d.ok);
    CHECK(d.error.find("unknown opcode") != std::string::npos);
    // `nop` with a register field set.
    Instr nop{opcode("nop"), 0, 0, 0, 0, 0, 0};
    uint64_t w = encode(nop, true) | (uint64_t{5} << 46);
    d = decode(w);
    CHECK_FALSE(d.ok);
    CHECK(d.error == "nop: unused field rd is not zero");
    // `sel` with bits above rs3.
    Instr sel{opcode("sel"), 0, 1, 2, 3, 4, 0};
    d = decode(encode(sel, true) | 0x100);
    CHECK_FALSE(d.ok);
}
