#include "base/suggest.hpp"

#include <catch2/catch.hpp>

using nesshi::base::closest;
using nesshi::base::did_you_mean;

TEST_CASE("a slip is one edit: a letter inserted, dropped, replaced or two swapped", "[unit][base]") {
    const std::vector<std::string> ops = {"fadd", "fsub", "fmul", "fdiv", "add", "addi"};
    CHECK(closest("fadx", ops) == "fadd");  // replaced
    CHECK(closest("fdd", ops) == "add");    // one edit from "fadd" and "add": the one of its length
    CHECK(closest("faadd", ops) == "fadd"); // inserted
    CHECK(closest("fmlu", ops) == "fmul");  // swapped
    CHECK(closest("FMUL", ops) == "fmul");  // case alone is no edit
    CHECK(did_you_mean("fadx", ops) == "; did you mean 'fadd'?");
}

TEST_CASE("nothing is suggested for a word far from every candidate, or for an exact one", "[unit][base]") {
    const std::vector<std::string> scenes = {"balls", "mount", "rings", "tetra", "tree", "gears"};
    CHECK_FALSE(closest("zzz", scenes));
    CHECK_FALSE(closest("sphere", scenes));
    CHECK_FALSE(closest("balls", scenes)); // an exact word is not a slip
    CHECK(did_you_mean("zzz", scenes).empty());
    CHECK_FALSE(closest("x", {}));
    CHECK_FALSE(closest("c", {"a", "b"})); // one edit from a letter is any other: no slip to see
    // Longer words allow an edit per three letters ("--modle": seven letters, up to two edits).
    CHECK(closest("--modle", {"--model", "--size", "--grid"}) == "--model");
    CHECK(closest("--sizee", {"--model", "--size", "--grid"}) == "--size");
}
