// Cell formats and notes shared by the tables and the summary.
#include "report_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

bool has_model(const PaperData& d, machine::Model m) {
    return std::find(d.models.begin(), d.models.end(), m) != d.models.end();
}

std::string format_published(const Published& p) {
    std::string s = p.value >= 100 ? fmt::format("{:.0f}", p.value) : fmt::format("{:.2f}", p.value);
    if (p.approximate) s = "≈" + s;
    if (p.reconstructed) s += "*";
    return s;
}

std::string format_range(const PublishedRange& r) { return fmt::format("{:.2f}–{:.2f}", r.lo, r.hi); }

std::string format_ratio(const std::array<int, 3>& r) { return fmt::format("{}:{}:{}", r[0], r[1], r[2]); }

std::string format_quotient(double num, double den) {
    return den > 0 && num > 0 ? fmt::format("{:.2f}", num / den) : kMissing;
}

std::string format_scale(int size) { return fmt::format("×{:g}", scale_to_paper(size)); }

std::vector<std::string> common_notes(const PaperData& d) {
    std::vector<std::string> notes;
    if (d.size != 512)
        notes.push_back(
            fmt::format("Note: ours at {0}x{0}; the paper's values are for 512x512. Columns marked {1} are ours scaled "
                        "by (512/{0})² to compare (approximate: the machine traces (size+1)² pixel corners).",
                        d.size, format_scale(d.size)));
    std::vector<std::string> off_size;
    for (const std::string& s : d.scenes)
        if (!is_paper_scene_size(s)) off_size.push_back(s);
    if (!off_size.empty())
        notes.push_back(fmt::format("Note: {} {} not the paper's scene (size factor or file): the paper's columns are "
                                    "for its own scene of that name and shown for reference only.",
                                    fmt::join(off_size, ", "), off_size.size() == 1 ? "is" : "are"));
    return notes;
}

} // namespace nesshi::paper

namespace nesshi::paper {

double axis_step(double max) {
    if (max <= 0) return 1;
    const double raw = max / 4, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

std::string csv_field(std::uint64_t v, bool present) { return present ? std::to_string(v) : std::string(); }
std::string csv_field(double v, bool present) { return present ? fmt::format("{}", v) : std::string(); }
std::string csv_flag(bool b) { return b ? "1" : "0"; }

void add_published_csv(std::vector<std::string>& row, const Published* p) {
    row.push_back(p ? csv_field(p->value) : "");
    row.push_back(p ? csv_flag(p->reconstructed) : "");
    row.push_back(p ? csv_flag(p->approximate) : "");
}

void add_published_csv_header(std::vector<std::string>& header, const std::string& name) {
    header.push_back(name);
    header.push_back(name + "_reconstructed");
    header.push_back(name + "_approximate");
}

} // namespace nesshi::paper
