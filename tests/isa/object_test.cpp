// Object files: round trip, and defensive loading of truncated, corrupt and foreign files.
#include "isa/object.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace nesshi::isa;

namespace {
ObjectFile sample() {
    ObjectFile o;
    o.machine = "os";
    o.machine_fingerprint = 0x1234567890abcdefull;
    Instr add{opcode("add"), 0, 1, 2, 3, 0, 0};
    Instr fadd{opcode("fadd"), 2, 4, 5, 6, 0, 0};
    Instr halt{opcode("halt"), 0, 0, 0, 0, 0, 0};
    o.code = {encode(add, false), encode(fadd, true), encode(halt, true)};
    o.data = {{0x100, {1, 2, 3, 4, 5}}};
    o.symbols = {{"start", SymbolKind::Code, 0, true}, {"table", SymbolKind::Data, 0x100, false}};
    o.files = {"a.s"};
    o.lines = {{0, 3}, {0, 4}};
    return o;
}

std::string load_error(const std::vector<uint8_t>& bytes) {
    try {
        ObjectFile o = read_object(bytes, "x.o");
        decode_bundles(o);
    } catch (const ObjectError& e) {
        return e.what();
    }
    return {};
}
} // namespace

TEST_CASE("objects round-trip through bytes") {
    ObjectFile o = sample();
    auto bytes = write_object(o);
    ObjectFile back = read_object(bytes, "x.o");
    CHECK(back == o);
    CHECK(write_object(back) == bytes);
    auto bundles = decode_bundles(back);
    REQUIRE(bundles.size() == 2);
    CHECK(bundles[0].size() == 2);
    CHECK(bundles[1][0].opcode == opcode("halt"));
}

TEST_CASE("every truncation is rejected cleanly") {
    auto bytes = write_object(sample());
    for (size_t n = 0; n < bytes.size(); ++n) {
        std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + long(n));
        INFO(n);
        CHECK_FALSE(load_error(cut).empty());
    }
}

TEST_CASE("foreign files and bad versions are named as such") {
    std::vector<uint8_t> elf = {0x7f, 'E', 'L', 'F', 2, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    CHECK(load_error(elf) == "x.o: error: not a Nesshisen object file (bad magic)");
    auto bytes = write_object(sample());
    bytes[8] = 9;
    CHECK(load_error(bytes) == "x.o: error: object format version 9 (this tool reads 1)");
}

// A symbol name is printed by dis and written into --stats-json: a name that is not an identifier
// (a byte 0xff broke the JSON after the whole run) is refused when the object is read.
TEST_CASE("symbol names must be identifiers") {
    for (const std::string& bad : {std::string("a\xff"), std::string("two words"), std::string("9lives"), std::string("a\"b")}) {
        ObjectFile o = sample();
        o.symbols[0].name = bad;
        INFO(bad);
        CHECK(load_error(write_object(o)).find("is not an identifier") != std::string::npos);
    }
    ObjectFile o = sample();
    o.symbols[0].name = "a\xff";
    CHECK(load_error(write_object(o)).find("symbol name 'a\\xff' is not an identifier") != std::string::npos);
    o.symbols[0].name = "_.x$9";
    CHECK(load_error(write_object(o)).empty());
}

TEST_CASE("random corruption never crashes and is always reported") {
    auto good = write_object(sample());
    std::mt19937 rng(7);
    for (int k = 0; k < 3000; ++k) {
        auto bytes = good;
        int flips = 1 + int(rng() % 4);
        for (int i = 0; i < flips; ++i) bytes[rng() % bytes.size()] ^= uint8_t(1 + rng() % 255);
        if (bytes == good) continue;
        CHECK_FALSE(load_error(bytes).empty());
    }
}

TEST_CASE("random bytes with a valid checksum are handled without a crash") {
    // Past the CRC the structural checks must hold on their own: forge checksums.
    auto good = write_object(sample());
    std::mt19937 rng(11);
    int rejected = 0;
    for (int k = 0; k < 3000; ++k) {
        auto bytes = good;
        bytes[10 + rng() % (bytes.size() - 14)] ^= uint8_t(1 + rng() % 255);
        uint32_t c = crc32(bytes.data(), bytes.size() - 4);
        for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + i] = uint8_t(c >> (8 * i));
        rejected += !load_error(bytes).empty();
    }
    CHECK(rejected > 0);
}

TEST_CASE("illegal code words are reported with their position") {
    ObjectFile o = sample();
    o.code[1] = uint64_t{127} << 56 | kEndOfBundle;
    CHECK(load_error(write_object(o)) ==
          "illegal encoding 0xff00000000000000 at word 1 (bundle 0): unknown opcode 127");
    o = sample();
    o.code.back() &= ~kEndOfBundle;
    o.lines.clear();
    CHECK(load_error(write_object(o)) == "the last bundle (1) has no end-of-bundle marker");
}
