// The line lexer (see lexer.hpp).
#include "lexer.hpp"

#include "isa/identifier.hpp"

#include <cctype>

namespace nesshi::assembler {

namespace {
using isa::ident_char;
using isa::ident_start;
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

int digit_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 99;
}

// Reads an integer or float literal starting at i; advances i past it.
Token number(std::string_view s, size_t& i) {
    Token t{Tok::Int, "", 0, int(i) + 1};
    size_t start = i;
    int base = 10;
    if (s[i] == '0' && i + 1 < s.size() && (s[i + 1] == 'x' || s[i + 1] == 'X')) base = 16;
    if (s[i] == '0' && i + 1 < s.size() && (s[i + 1] == 'b' || s[i + 1] == 'B')) base = 2;
    if (base != 10) i += 2;
    bool is_float = false;
    while (i < s.size()) {
        char c = s[i];
        if (base == 10 && (c == '.' || c == 'e' || c == 'E')) {
            is_float = true;
            ++i;
            if ((c == 'e' || c == 'E') && i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
            continue;
        }
        if (!ident_char(c)) break;
        ++i;
    }
    t.text = std::string(s.substr(start, i - start));
    if (is_float) {
        t.kind = Tok::Float;
        return t;
    }
    size_t p = base == 10 ? 0 : 2;
    if (p == t.text.size()) {
        t.kind = Tok::Bad;
        t.text = "malformed number '" + t.text + "'";
        return t;
    }
    uint64_t v = 0;
    for (; p < t.text.size(); ++p) {
        int d = digit_value(t.text[p]);
        if (d >= base) {
            t.kind = Tok::Bad;
            t.text = "malformed number '" + t.text + "'";
            return t;
        }
        if (v > (UINT64_MAX - uint64_t(d)) / uint64_t(base)) {
            t.kind = Tok::Bad;
            t.text = "number '" + t.text + "' is too large";
            return t;
        }
        v = v * uint64_t(base) + uint64_t(d);
    }
    t.value = v;
    return t;
}

// Reads one possibly escaped character of a string or char literal.
bool read_char(std::string_view s, size_t& i, char& out) {
    if (i >= s.size()) return false;
    if (s[i] != '\\') {
        out = s[i++];
        return true;
    }
    if (++i >= s.size()) return false;
    switch (s[i++]) {
    case 'n': out = '\n'; return true;
    case 't': out = '\t'; return true;
    case 'r': out = '\r'; return true;
    case '0': out = '\0'; return true;
    case '\\': out = '\\'; return true;
    case '\'': out = '\''; return true;
    case '"': out = '"'; return true;
    default: return false;
    }
}
} // namespace

bool is_identifier(std::string_view name) { return isa::is_identifier(name); }

bool is_register_name(std::string_view name) {
    return name.size() > 1 && (name[0] == 'r' || name[0] == 'f') &&
           name.find_first_not_of("0123456789", 1) == std::string_view::npos;
}

std::string quote(std::string_view text) {
    std::string out = "\"";
    for (char c : text) {
        switch (c) {
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        case '\r': out += "\\r"; break;
        case '\0': out += "\\0"; break;
        case '\\': out += "\\\\"; break;
        case '"': out += "\\\""; break;
        default: out += c;
        }
    }
    return out + '"';
}

std::vector<Token> lex_line(std::string_view s) {
    std::vector<Token> out;
    size_t i = 0;
    while (i < s.size()) {
        if (!out.empty() && out.back().end == 0) out.back().end = int(i) + 1;
        char c = s[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
            ++i;
            continue;
        }
        if (c == '#' || (c == '/' && i + 1 < s.size() && s[i + 1] == '/')) break;
        int col = int(i) + 1;
        if (digit(c)) {
            out.push_back(number(s, i));
            continue;
        }
        if (ident_start(c)) {
            size_t start = i;
            while (i < s.size() && ident_char(s[i])) ++i;
            out.push_back({Tok::Ident, std::string(s.substr(start, i - start)), 0, col});
            continue;
        }
        if (c == '"') {
            ++i;
            std::string text;
            bool ok = false;
            while (i < s.size()) {
                if (s[i] == '"') {
                    ++i;
                    ok = true;
                    break;
                }
                char ch;
                if (!read_char(s, i, ch)) break;
                text += ch;
            }
            if (ok) out.push_back({Tok::String, std::move(text), 0, col});
            else {
                out.push_back({Tok::Bad, "unterminated or malformed string", 0, col});
                i = s.size();
                break;
            }
            continue;
        }
        if (c == '\'') {
            ++i;
            char ch = 0;
            if (read_char(s, i, ch) && i < s.size() && s[i] == '\'') {
                ++i;
                out.push_back({Tok::Int, std::string(s.substr(size_t(col - 1), i - size_t(col - 1))),
                               uint64_t(static_cast<unsigned char>(ch)), col});
            } else {
                out.push_back({Tok::Bad, "malformed character literal", 0, col});
                i = s.size();
                break;
            }
            continue;
        }
        if ((c == '<' || c == '>') && i + 1 < s.size() && s[i + 1] == c) {
            out.push_back({Tok::Punct, std::string(2, c), 0, col});
            i += 2;
            continue;
        }
        static constexpr std::string_view kPunct = ",;:{}()+-*/%&|^~";
        if (kPunct.find(c) != std::string_view::npos) {
            out.push_back({Tok::Punct, std::string(1, c), 0, col});
            ++i;
            continue;
        }
        out.push_back({Tok::Bad, "unexpected character '" + std::string(1, c) + "'", 0, col});
        ++i;
    }
    if (!out.empty() && out.back().end == 0) out.back().end = int(i) + 1;
    return out;
}

} // namespace nesshi::assembler
