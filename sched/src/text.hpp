// Internal: the line handling of the schedulers' input texts (linear assembly, .pk blocks).
#pragma once

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

// The lines of `text` without their '\n'; a final line without one counts, an empty tail does not.
inline std::vector<std::string> split_lines(std::string_view text) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t nl = text.find('\n', start);
        if (nl == std::string_view::npos) {
            if (start < text.size()) lines.emplace_back(text.substr(start));
            break;
        }
        lines.emplace_back(text.substr(start, nl - start));
        start = nl + 1;
    }
    return lines;
}

} // namespace nesshi::sched
