// Constant expressions: + - * / % << >> & | ^ ~ unary -, parentheses, over numbers and names.
#pragma once

#include "lexer.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

namespace nesshi::assembler {

// Looks a name up; nullopt when undefined (the evaluator then reports it). `err` may be set to
// a more specific reason (e.g. a cyclic .equ).
using Resolver = std::function<std::optional<int64_t>(const Token& name, std::string& err)>;

struct ExprResult {
    bool ok = false;
    int64_t value = 0;
    std::string error;
    int col = 0; // column of the token at fault
};

// Most operators and parentheses one evaluation may nest, counting the evaluations it starts
// through its resolver when they share a counter (below): deeper is "expression nested too deeply".
inline constexpr int kMaxExprNesting = 256;

// Evaluates the whole token span as one expression (trailing tokens are an error). `nesting`, when
// given, is the depth counter shared with the evaluations `resolve` starts (a .equ evaluating the
// names it uses), so the limit bounds the whole chain, and the stack, not each link.
ExprResult eval_expr(std::span<const Token> toks, const Resolver& resolve, int* nesting = nullptr);

// Whether `toks` is syntactically an expression (no evaluation, names accepted).
bool is_expr(std::span<const Token> toks);

} // namespace nesshi::assembler
