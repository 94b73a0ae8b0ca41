// The constant-expression evaluator (see expr.hpp). Arithmetic wraps in 64 bits (no UB).
#include "expr.hpp"

namespace nesshi::assembler {

namespace {

struct ExprParser {
    std::span<const Token> t;
    const Resolver* resolve; // null: syntax check only
    size_t i = 0;
    ExprResult err;

    bool failed() const { return !err.error.empty(); }
    void fail(std::string msg, int col) {
        if (failed()) return;
        err.error = std::move(msg);
        err.col = col;
    }
    int col() const { return i < t.size() ? t[i].col : (t.empty() ? 1 : t.back().col); }
    bool at(std::string_view p) const { return i < t.size() && t[i].is(p); }

    static int64_t wrap(uint64_t v) { return static_cast<int64_t>(v); }

    int own_depth = 0;
    int* depth = &own_depth; // or the counter shared with nested evaluations

    int64_t primary() {
        if (failed()) return 0;
        if (++*depth > kMaxExprNesting) {
            --*depth;
            fail("expression nested too deeply", col());
            return 0;
        }
        struct Leave { int& d; ~Leave() { --d; } } leave{*depth};
        if (i >= t.size()) {
            fail("expected an expression", col());
            return 0;
        }
        const Token& k = t[i];
        if (k.is("(")) {
            ++i;
            int64_t v = binary(0);
            if (!at(")")) fail("expected ')'", col());
            else ++i;
            return v;
        }
        if (k.is("-") || k.is("~") || k.is("+")) {
            ++i;
            int64_t v = primary();
            if (k.is("-")) return wrap(0 - static_cast<uint64_t>(v));
            if (k.is("~")) return ~v;
            return v;
        }
        if (k.kind == Tok::Int) {
            ++i;
            return wrap(k.value);
        }
        if (k.kind == Tok::Ident) {
            ++i;
            if (!resolve) return 0;
            std::string why;
            auto v = (*resolve)(k, why);
            if (!v) fail(why.empty() ? "undefined symbol '" + k.text + "'" : why, k.col);
            return v.value_or(0);
        }
        if (k.kind == Tok::Float) fail("a float literal is not allowed here", k.col);
        else if (k.kind == Tok::Bad) fail(k.text, k.col);
        else fail("unexpected '" + k.text + "' in expression", k.col);
        return 0;
    }

    static int prec(const Token& k) {
        if (k.kind != Tok::Punct) return -1;
        const std::string& s = k.text;
        if (s == "|") return 1;
        if (s == "^") return 2;
        if (s == "&") return 3;
        if (s == "<<" || s == ">>") return 4;
        if (s == "+" || s == "-") return 5;
        if (s == "*" || s == "/" || s == "%") return 6;
        return -1;
    }

    int64_t apply(const Token& op, int64_t a, int64_t b) {
        if (!resolve) return 0; // syntax check only: values are not known yet
        uint64_t ua = static_cast<uint64_t>(a), ub = static_cast<uint64_t>(b);
        const std::string& s = op.text;
        if (s == "+") return wrap(ua + ub);
        if (s == "-") return wrap(ua - ub);
        if (s == "*") return wrap(ua * ub);
        if (s == "&") return a & b;
        if (s == "|") return a | b;
        if (s == "^") return a ^ b;
        if (s == "<<" || s == ">>") {
            if (b < 0 || b > 63) {
                fail("shift amount out of range (0..63)", op.col);
                return 0;
            }
            return s == "<<" ? wrap(ua << b) : (a >> b);
        }
        // / and %
        if (b == 0) {
            fail("division by zero", op.col);
            return 0;
        }
        if (a == INT64_MIN && b == -1) return s == "/" ? a : 0;
        return s == "/" ? a / b : a % b;
    }

    int64_t binary(int min_prec) {
        int64_t lhs = primary();
        while (!failed() && i < t.size()) {
            int p = prec(t[i]);
            if (p < 0 || p < min_prec) break;
            const Token& op = t[i++];
            int64_t rhs = binary(p + 1);
            if (failed()) break;
            lhs = apply(op, lhs, rhs);
        }
        return lhs;
    }
};

} // namespace

ExprResult eval_expr(std::span<const Token> toks, const Resolver& resolve, int* nesting) {
    ExprParser p{toks, &resolve, 0, {}};
    if (nesting) p.depth = nesting;
    int64_t v = p.binary(0);
    if (!p.failed() && p.i < toks.size()) p.fail("unexpected '" + toks[p.i].text + "' after expression", toks[p.i].col);
    if (p.failed()) return p.err;
    return {true, v, {}, 0};
}

bool is_expr(std::span<const Token> toks) {
    ExprParser p{toks, nullptr, 0, {}};
    p.binary(0);
    return !p.failed() && p.i == toks.size();
}

} // namespace nesshi::assembler
