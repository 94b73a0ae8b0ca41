// What a name in assembly may be, in one place: the assembler's lexer reads identifiers with
// these rules, the object reader accepts only such symbol names, and the machine loader only
// such slot names, so whatever the disassembler prints re-assembles.
#pragma once

#include <string_view>

namespace nesshi::isa {

// A label, symbol or .equ name: [A-Za-z_.$][A-Za-z0-9_.$]* (ASCII only, whatever the locale).
constexpr bool ident_start(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '.' || c == '$';
}
constexpr bool ident_char(char c) { return ident_start(c) || (c >= '0' && c <= '9'); }
constexpr bool is_identifier(std::string_view s) {
    if (s.empty() || !ident_start(s[0])) return false;
    for (char c : s)
        if (!ident_char(c)) return false;
    return true;
}

// A slot name (the `iu0:` of a pinned op): [A-Za-z_][A-Za-z0-9_]*, no '.' or '$', which would
// read as a directive or a symbol.
constexpr bool is_slot_name(std::string_view s) {
    if (!is_identifier(s) || s[0] == '.' || s[0] == '$') return false;
    for (char c : s)
        if (c == '.' || c == '$') return false;
    return true;
}

} // namespace nesshi::isa
