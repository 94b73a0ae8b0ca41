// The lines of a text, as the tools that read assembly and source texts line by line split it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nesshi::base {

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

} // namespace nesshi::base
