// Splits one source line into tokens with their columns; comments (`#`, `//`) end the line.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::assembler {

enum class Tok : uint8_t {
    Ident,  // names, mnemonics, registers, directives (may start with '.')
    Int,    // integer literal (decimal, 0x, 0b, 'c')
    Float,  // decimal literal with '.' or an exponent
    String, // "..." (text holds the contents, escapes resolved)
    Punct,  // one of , ; : { } ( ) + - * / % & | ^ ~ and the two-char << >>
    Bad,    // a character or literal the lexer cannot read (text says why)
};

struct Token {
    Tok kind;
    std::string text; // spelling (for Punct the operator; for Int/Float the literal)
    uint64_t value = 0;
    int col = 1; // 1-based column of the first character
    int end = 0; // 1-based column just past its last character in the source
    bool is(std::string_view punct) const { return kind == Tok::Punct && text == punct; }
};

std::vector<Token> lex_line(std::string_view line);

// Whether `name` lexes as one identifier (a label, unless a register or slot name).
bool is_identifier(std::string_view name);
// r or f followed by digits only ("r7", "f200"): never a label.
bool is_register_name(std::string_view name);
// A string literal that lex_line reads back as exactly `text` (quotes, backslashes and
// newlines escaped).
std::string quote(std::string_view text);

} // namespace nesshi::assembler
