// The check of a numeric option, its bounds in words: "--pes must be an integer between 1 and 64
// (got '0')" instead of CLI11's "Value 0 not in range 0.000000 to 1.79e308". Every numeric
// option of every command has one (an out-of-range value is a usage error, exit 2).
#pragma once

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <charconv>
#include <string>
#include <system_error>
#include <type_traits>

namespace nesshi::cli {

// The value must parse as a T (all of it) and lie in [lo, hi]. CLI11 prefixes the option's name;
// errors.cpp prints "NAME must be ...".
template <class T>
CLI::Validator between(T lo, T hi) {
    const std::string words =
        fmt::format("must be {} between {} and {}", std::is_integral_v<T> ? "an integer" : "a number", lo, hi);
    return CLI::Validator(
        [=](std::string& s) -> std::string {
            T v{};
            const char* end = s.data() + s.size();
            const auto [p, ec] = std::from_chars(s.data(), end, v);
            if (ec != std::errc() || p != end || !(v >= lo && v <= hi)) return fmt::format("{} (got '{}')", words, s);
            return {};
        },
        fmt::format("{} to {}", lo, hi));
}

} // namespace nesshi::cli
