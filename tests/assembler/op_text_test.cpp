// split_operation and register_named: an operation's text split as the parser reads it.
#include "assembler/op_text.hpp"

#include <catch2/catch.hpp>

using namespace nesshi;

TEST_CASE("split_operation: slot, mnemonic, operands with their columns, parentheses and comments", "[unit][assembler]") {
    const std::string text = "fpu0: fmadd %acc,f1 ,  4(r2)  # a comment, with a comma";
    const assembler::OperationText op = assembler::split_operation(text);
    CHECK(op.slot == "fpu0");
    CHECK(op.mnemonic == "fmadd");
    CHECK(op.mnemonic_col == 6);
    REQUIRE(op.operands.size() == 3);
    CHECK(op.operands[0].text == "%acc");
    CHECK(op.operands[1].text == "f1");
    CHECK(op.operands[2].text == "4(r2)");
    for (const assembler::OperandText& o : op.operands) CHECK(text.substr(o.col, o.text.size()) == o.text);
    // A comma inside parentheses does not split; an empty operand stays, at its place.
    const auto odd = assembler::split_operation("sw r1, (2, 3)(r4),");
    REQUIRE(odd.operands.size() == 3);
    CHECK(odd.operands[1].text == "(2, 3)(r4)");
    CHECK(odd.operands[2].text.empty());
    // Directives split the same way; no operands, no operation.
    CHECK(assembler::split_operation(".noalias r1, r2").mnemonic == ".noalias");
    CHECK(assembler::split_operation("halt").operands.empty());
    CHECK(assembler::split_operation("   # nothing").mnemonic.empty());
}

TEST_CASE("register_named: r and f below the register limit, nothing else", "[unit][assembler]") {
    CHECK(assembler::register_named("r7") == std::pair{isa::RegFile::Int, 7});
    CHECK(assembler::register_named("f127") == std::pair{isa::RegFile::Float, 127});
    CHECK_FALSE(assembler::register_named("f128"));
    CHECK_FALSE(assembler::register_named("r99999999999"));
    CHECK_FALSE(assembler::register_named("r"));
    CHECK_FALSE(assembler::register_named("x1"));
    CHECK_FALSE(assembler::register_named("r1a"));
    CHECK_FALSE(assembler::register_named("%v"));
}

TEST_CASE("split_operation keeps the text as written, for messages and carets", "[unit][assembler]") {
    // A mnemonic the lexer cannot read is still the source's text, not the lexer's complaint.
    CHECK(assembler::split_operation("@foo r1, r2").mnemonic == "@foo");
    // An empty last operand sits just after its comma, not after a comment.
    const std::string text = ".trip 5,   # expected count missing";
    const auto op = assembler::split_operation(text);
    REQUIRE(op.operands.size() == 2);
    CHECK(op.operands[1].text.empty());
    CHECK(op.operands[1].col == text.find(',') + 1);
}
