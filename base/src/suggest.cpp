#include "base/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace nesshi::base {

namespace {

// Optimal string alignment distance (Damerau-Levenshtein without repeated edits of a
// substring), case-insensitive: `Fadd` is one slip from nothing but `fadd`.
std::size_t distance(std::string_view a, std::string_view b) {
    auto same = [](char x, char y) { return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y)); };
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (same(a[i - 1], b[j - 1]) ? 0 : 1)});
            if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1])) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

} // namespace

std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& candidates) {
    if (word.size() < 3) return std::nullopt; // one edit from "c" is any other letter
    const std::size_t most = std::max<std::size_t>(1, word.size() / 3);
    std::optional<std::string> best;
    std::size_t best_distance = most + 1, best_gap = 0;
    auto gap = [&](const std::string& c) { return c.size() > word.size() ? c.size() - word.size() : word.size() - c.size(); };
    for (const std::string& c : candidates) {
        if (c == word || c.empty()) continue;
        // Equally near: the one of the word's length first (a letter replaced or two swapped
        // rather than one added or dropped), then the first.
        if (const std::size_t d = distance(word, c); d < best_distance || (d == best_distance && gap(c) < best_gap)) {
            best_distance = d;
            best_gap = gap(c);
            best = c;
        }
    }
    return best;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
    const std::optional<std::string> c = closest(word, candidates);
    return c ? "; did you mean '" + *c + "'?" : "";
}

} // namespace nesshi::base
