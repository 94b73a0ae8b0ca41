// Comma-separated option values (--scenes a,b --grids 20,50), shared by the paper commands.
#pragma once

#include "errors.hpp"

#include <fmt/format.h>

#include <charconv>
#include <string>
#include <vector>

namespace nesshi::cli {

inline std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
        parts.push_back(s.substr(start, comma - start));
    parts.push_back(s.substr(start));
    return parts;
}

// Integers; their range is the caller's to check.
inline std::vector<int> parse_grids(const std::string& s) {
    std::vector<int> grids;
    for (const std::string& part : split_list(s)) {
        int g = 0;
        auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), g);
        if (ec != std::errc() || p != part.data() + part.size()) throw UsageError(fmt::format("bad grid '{}'", part));
        grids.push_back(g);
    }
    return grids;
}

} // namespace nesshi::cli
