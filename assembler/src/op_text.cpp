#include "assembler/op_text.hpp"

#include "lexer.hpp"

#include <charconv>

namespace nesshi::assembler {

OperationText split_operation(std::string_view text) {
    const std::vector<Token> toks = lex_line(text);
    OperationText out;
    std::size_t i = 0;
    if (toks.size() >= 2 && toks[0].kind == Tok::Ident && toks[1].is(":")) {
        out.slot = toks[0].text;
        i = 2;
    }
    if (i >= toks.size()) return out;
    // The mnemonic as written: up to the first blank (tokens that touch it are part of it, so a
    // misspelt `@foo` is quoted whole in a message).
    out.mnemonic_col = static_cast<std::size_t>(toks[i].col - 1);
    int end = toks[i].end;
    for (++i; i < toks.size() && toks[i].col == end && !toks[i].is(","); ++i) end = toks[i].end;
    out.mnemonic = std::string(text.substr(out.mnemonic_col, static_cast<std::size_t>(end - 1) - out.mnemonic_col));
    if (i >= toks.size()) return out;
    int depth = 0;
    std::size_t first = static_cast<std::size_t>(toks[i].col - 1), last_end = first;
    bool empty = true;
    auto close = [&](std::size_t at) {
        out.operands.push_back({empty ? "" : std::string(text.substr(first, last_end - first)), empty ? at : first});
        empty = true;
    };
    for (; i < toks.size(); ++i) {
        const Token& t = toks[i];
        if (t.is("(")) ++depth;
        if (t.is(")")) --depth;
        if (t.is(",") && depth == 0) {
            close(static_cast<std::size_t>(t.col - 1));
            continue;
        }
        if (empty) first = static_cast<std::size_t>(t.col - 1), empty = false;
        last_end = static_cast<std::size_t>(t.end - 1);
    }
    close(static_cast<std::size_t>(toks.back().end - 1)); // an empty last operand: just after its comma
    return out;
}

std::optional<std::pair<isa::RegFile, int>> register_named(std::string_view name) {
    if (!is_register_name(name)) return std::nullopt;
    int n = 0;
    const auto [end, ec] = std::from_chars(name.data() + 1, name.data() + name.size(), n);
    if (ec != std::errc{} || end != name.data() + name.size() || n >= isa::kMaxRegs) return std::nullopt;
    return std::pair{name[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float, n};
}

} // namespace nesshi::assembler
