// docs/isa.md is generated from the table; this keeps the committed copy current.
#include "isa/ops.hpp"
#include "isa/reference.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <regex>
#include <sstream>

TEST_CASE("docs/isa.md matches the operation table") {
    std::ifstream in(NESSHI_SOURCE_DIR "/docs/isa.md");
    REQUIRE(in.good());
    std::stringstream ss;
    ss << in.rdbuf();
    INFO("regenerate with: build/nesshi isa --markdown > docs/isa.md");
    CHECK(ss.str() == nesshi::isa::isa_reference_markdown());
}

// The operands column names registers as the meaning column does (a store's value is rs2 or
// fs2, its base rs1), for every row of the table.
TEST_CASE("docs/isa.md names each operation's registers as its summary does") {
    const std::string md = nesshi::isa::isa_reference_markdown();
    // The summary cell may hold escaped bars (`or`: rd = rs1 \| rs2), never a bare one.
    const std::regex row(
        R"(\| \d+ \| `([a-z]+)` \| `([^`]*)` \| [^|]+ \| [^|]+ \| ((?:[^|\\\n]|\\\|)+) \|\n)");
    const std::regex reg(R"(\b[rf](d|s\d)\b)");
    int rows = 0;
    for (std::sregex_iterator it(md.begin(), md.end(), row), end; it != end; ++it, ++rows) {
        const std::string mnemonic = (*it)[1], operands = (*it)[2], summary = (*it)[3];
        for (std::sregex_iterator r(operands.begin(), operands.end(), reg); r != end; ++r) {
            INFO(mnemonic << ": " << operands << " | " << summary);
            CHECK(summary.find(r->str()) != std::string::npos);
        }
    }
    CHECK(rows == nesshi::isa::kNumOps);
    CHECK(md.find("| `sw` | `rs2, imm(rs1)` |") != std::string::npos);
    CHECK(md.find("| `fsw` | `fs2, imm(rs1)` |") != std::string::npos);
}
