// One operation's text split the way the assembler's parser reads it, for tools that rewrite
// operations as text before assembling them (the schedulers' virtual registers, the legalizer's
// split bundles): the same lexer, so a comment ends it and commas inside parentheses do not
// split an operand.
//
//   const auto op = assembler::split_operation("fpu0: fmadd %acc, f1, 4(r2)  # note");
//   op.slot;               // "fpu0"
//   op.mnemonic;           // "fmadd"
//   op.operands[2].text;   // "4(r2)", op.operands[2].col its offset in the text
//   assembler::register_named("f12");  // {Float, 12}
#pragma once

#include "isa/encoding.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nesshi::assembler {

struct OperandText {
    std::string text;     // as written, without the surrounding blanks ("" for an empty one)
    std::size_t col = 0;  // 0-based offset of its first character in the operation's text
};

struct OperationText {
    std::string slot;     // "fpu0" for "fpu0: fadd ..."; "" without a slot prefix
    std::string mnemonic; // "" when the text holds no operation
    std::size_t mnemonic_col = 0;
    std::vector<OperandText> operands;
};

OperationText split_operation(std::string_view text);

// A register's name as the assembler reads it: `r` or `f` and a number below isa::kMaxRegs
// ("r7": {Int, 7}); nullopt for anything else. Whether the machine has it is the caller's check.
std::optional<std::pair<isa::RegFile, int>> register_named(std::string_view name);

} // namespace nesshi::assembler
