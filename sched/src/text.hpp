// Internal: the line handling of the schedulers' input texts (linear assembly, .pk blocks).
#pragma once

#include "isa/ops.hpp"

#include "base/lines.hpp"

#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::sched {

inline std::string trim(std::string_view s) {
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return std::string(s.substr(a, b - a));
}

// The text before a '#' comment, trimmed.
inline std::string strip_comment(std::string_view s) {
    const std::size_t h = s.find('#');
    return trim(h == std::string_view::npos ? s : s.substr(0, h));
}

using base::split_lines; // base/lines.hpp

// The comma-separated operands of an op, trimmed; commas inside parentheses do not split.
inline std::vector<std::string> split_operands(const std::string& s) {
    std::vector<std::string> out;
    if (trim(s).empty()) return out;
    int depth = 0;
    std::string cur;
    for (char c : s) {
        if (c == '(') ++depth;
        if (c == ')') --depth;
        if (c == ',' && depth == 0) {
            out.push_back(trim(cur));
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(trim(cur));
    return out;
}

// A register name ("r5", "f71") into its file and number.
inline bool parse_reg(std::string_view s, isa::RegFile& f, int& r) {
    if (s.size() < 2 || (s[0] != 'r' && s[0] != 'f')) return false;
    int v = 0;
    for (char c : s.substr(1)) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
        v = v * 10 + (c - '0');
        if (v > 1000) return false;
    }
    f = s[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float;
    r = v;
    return true;
}

} // namespace nesshi::sched
