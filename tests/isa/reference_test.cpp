// docs/isa.md is generated from the table; this keeps the committed copy current.
#include "isa/reference.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

TEST_CASE("docs/isa.md matches the operation table") {
    std::ifstream in(NESSHI_SOURCE_DIR "/docs/isa.md");
    REQUIRE(in.good());
    std::stringstream ss;
    ss << in.rdbuf();
    INFO("regenerate with: build/nesshi isa --markdown > docs/isa.md");
    CHECK(ss.str() == nesshi::isa::isa_reference_markdown());
}
