#include "base/error.hpp"

#include <catch2/catch.hpp>

using nesshi::base::Error;
using nesshi::base::format_error;
using nesshi::base::SourceLoc;

TEST_CASE("a location prints only the parts it knows", "[unit][base]") {
    CHECK(SourceLoc().str().empty());
    CHECK_FALSE(SourceLoc().known());
    CHECK(SourceLoc("a.s").str() == "a.s");
    CHECK(SourceLoc("a.s", 3).str() == "a.s:3");
    CHECK(SourceLoc("a.s", 3, 7).str() == "a.s:3:7");
    CHECK(SourceLoc("a.s", 0, 7).str() == "a.s"); // a column without a line means nothing
}

TEST_CASE("an error keeps its location and message apart, and what() joins them", "[unit][base]") {
    const Error e(SourceLoc("scene.nff", 12, 3), "expected a radius");
    CHECK(std::string(e.what()) == "scene.nff:12:3: error: expected a radius");
    CHECK(e.message() == "expected a radius");
    CHECK(e.loc().line == 12);
    CHECK(*e.loc().file == "scene.nff");
    const Error bare("no scene");
    CHECK(std::string(bare.what()) == "no scene");
    CHECK_FALSE(bare.loc().known());
    CHECK(format_error(SourceLoc("x.o"), "truncated") == "x.o: error: truncated");
}

TEST_CASE("records of one file share its name", "[unit][base]") {
    auto file = std::make_shared<const std::string>("big.nff");
    const SourceLoc a(file, 1, 1), b(file, 2, 5);
    CHECK(a.file.get() == b.file.get());
    CHECK(b.str() == "big.nff:2:5");
}
