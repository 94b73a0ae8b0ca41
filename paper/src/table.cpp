// A report table as Markdown (for reading) and CSV (for plotting), and the number format they share.
#include "paper/paper.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

std::string format_mcycles(double cycles) {
    const double m = cycles / 1e6;
    if (m == 0) return "0";
    // 4 significant digits in fixed notation: 16846, 4.581, 0.0001234.
    const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(m))));
    const int decimals = std::clamp(3 - magnitude, 0, 12);
    return fmt::format("{:.{}f}", m, decimals);
}

std::string to_markdown(const Table& t) {
    std::string o = fmt::format("## {}\n\n", t.title);
    auto row = [&](const std::vector<std::string>& cells) {
        o += "|";
        for (const std::string& c : cells) o += fmt::format(" {} |", c);
        o += "\n";
    };
    row(t.header);
    o += "|";
    for (std::size_t i = 0; i < t.header.size(); ++i) o += i == 0 ? "---|" : "---:|"; // numbers right-aligned
    o += "\n";
    for (const auto& r : t.rows) row(r);
    if (!t.notes.empty()) o += "\n";
    for (const std::string& n : t.notes) o += n + "\n\n";
    return o;
}

std::string to_csv(const Table& t) {
    auto cell = [](const std::string& c) {
        if (c.find_first_of(",\"\n") == std::string::npos) return c;
        std::string q = "\"";
        for (char ch : c) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        return q + "\"";
    };
    std::string o;
    auto row = [&](const std::vector<std::string>& cells) {
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (i) o += ',';
            o += cell(cells[i]);
        }
        o += "\n";
    };
    const bool tidy = !t.csv_header.empty();
    row(tidy ? t.csv_header : t.header);
    for (const auto& r : tidy ? t.csv_rows : t.rows) row(r);
    return o;
}

} // namespace nesshi::paper
