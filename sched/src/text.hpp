// Internal: the line handling of the schedulers' input texts (linear assembly, .pk blocks). An
// operation's own text is split by the assembler (assembler/op_text.hpp).
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

} // namespace nesshi::sched
