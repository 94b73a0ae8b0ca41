// The gap chart: per scene x grid x stage, on a log axis of cycles, our cycles (circle), the paper's
// (square), the part of the gap explained by kernel speed and the adopted hypothesis (green) and the
// rest (red).
#include "paper/gaps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

namespace {

constexpr double kLeft = 150, kRight = 760, kTop = 70, kRow = 17, kWidth = 1100;
constexpr double kGap = 8; // between a scene and grid's two rows and the next's: the separator's room

struct Axis {
    double lo = 7, hi = 11; // decades
    double x(double cycles) const { return kLeft + (std::log10(cycles) - lo) / (hi - lo) * (kRight - kLeft); }
};

} // namespace

std::string gaps_svg(std::span<const GapRow> rows) {
    Axis ax;
    double lo = 1e300, hi = 0;
    for (const GapRow& r : rows)
        for (double v : {r.paper_os, r.paper_ic, r.ours.os, r.ours.ic, r.os_explained, r.ic_explained}) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    if (hi > 0) {
        ax.lo = std::floor(std::log10(lo));
        ax.hi = std::max(ax.lo + 1, std::ceil(std::log10(hi)));
    }
    const double group = 2 * kRow + kGap;
    const double height = kTop + static_cast<double>(rows.size()) * group + 50;
    std::string o = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{:.0f}\" "
                                "font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
                                kWidth, height);
    o += "<text x=\"10\" y=\"18\" font-size=\"14\">Table 2 processing cycles, model V: ours against the paper's "
         "(log scale)</text>\n";
    o += "<circle cx=\"16\" cy=\"36\" r=\"4\" fill=\"black\"/><text x=\"24\" y=\"40\">ours</text>"
         "<rect x=\"70\" y=\"32\" width=\"8\" height=\"8\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>"
         "<text x=\"84\" y=\"40\">paper</text>"
         "<line x1=\"130\" y1=\"36\" x2=\"160\" y2=\"36\" stroke=\"#2a9d3a\" stroke-width=\"5\"/>"
         "<text x=\"166\" y=\"40\">explained: our kernels' speed x the adopted hypothesis</text>"
         "<line x1=\"520\" y1=\"36\" x2=\"550\" y2=\"36\" stroke=\"#d62728\" stroke-width=\"5\"/>"
         "<text x=\"556\" y=\"40\">unexplained (green above, red below the row: each may point either way)</text>\n";
    const double bottom = kTop + static_cast<double>(rows.size()) * group;
    for (double d = ax.lo; d <= ax.hi + 1e-9; d += 1) {
        const double x = ax.x(std::pow(10.0, d));
        o += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.0f}\" x2=\"{0:.1f}\" y2=\"{2:.0f}\" stroke=\"#ddd\"/>"
                         "<text x=\"{0:.1f}\" y=\"{3:.0f}\" text-anchor=\"middle\">1e{4:.0f}</text>\n",
                         x, kTop - 8, bottom, bottom + 16, d);
    }
    o += fmt::format("<text x=\"{:.0f}\" y=\"{:.0f}\" text-anchor=\"middle\">cycles</text>\n", (kLeft + kRight) / 2,
                     bottom + 32);
    double y = kTop;
    for (const GapRow& r : rows) {
        // The separator in the middle of the gap above the group, clear of both groups' labels.
        o += fmt::format("<line x1=\"10\" y1=\"{0:.0f}\" x2=\"{1}\" y2=\"{0:.0f}\" stroke=\"#bbb\"/>\n", y + kGap / 2 + 1,
                         kWidth - 10);
        y += kGap;
        struct S {
            const char* name;
            double ours, explained, paper;
        };
        for (const S& s : {S{"OS", r.ours.os, r.os_explained, r.paper_os}, S{"IC", r.ours.ic, r.ic_explained, r.paper_ic}}) {
            const double yc = y + kRow / 2;
            o += fmt::format("<text x=\"10\" y=\"{:.0f}\">{} {} {}</text>\n", yc + 4, r.scene, r.grid, s.name);
            o += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#2a9d3a\" "
                             "stroke-width=\"4\"/>\n",
                             ax.x(s.ours), yc - 2.5, ax.x(s.explained), yc - 2.5);
            o += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#d62728\" "
                             "stroke-width=\"4\"/>\n",
                             ax.x(s.explained), yc + 2.5, ax.x(s.paper), yc + 2.5);
            o += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" fill=\"black\"/>\n", ax.x(s.ours), yc);
            o += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"8\" height=\"8\" fill=\"none\" stroke=\"black\" "
                             "stroke-width=\"1.5\"/>\n",
                             ax.x(s.paper) - 4, yc - 4);
            o += fmt::format("<text x=\"{}\" y=\"{:.0f}\">paper/ours {:.2f}, unexplained {:.2f}</text>\n", kRight + 10,
                             yc + 4, s.paper / s.ours, s.paper / s.explained);
            y += kRow;
        }
    }
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::paper
