// A sweep's chart (chart.svg): one metric against one axis, a series per combination of the other
// swept axes. Series differ by marker shape and line dash as well as colour (readable in grey and
// by the colour-blind); a numeric axis joins its points, a categorical one (scenes, machines) does
// not and spreads each category's points apart so that equal values stay visible; labels that
// would collide turn; machine and scene files are named by their stem; values spanning 30x or more
// get a log axis unless the spec says y_scale.
#include "paper/sweep.hpp"

#include "report_format.hpp"
#include "sweep_metric.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

namespace nesshi::paper {
namespace {

using nlohmann::json;

// Okabe and Ito's palette, then shapes and dashes that tell series apart without colour.
constexpr const char* kColours[] = {"#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7", "#56B4E9", "#F0E442", "#000000"};
constexpr const char* kDashes[] = {"", "6 3", "2 3", "8 3 2 3", "10 4", "3 6"};
constexpr int kShapes = 6;
constexpr double kCharWidth = 6.8; // px per character at 12 px, a bound for sans-serif digits and letters

// A marker of shape `k` centred on (x, y).
std::string marker(int k, double x, double y, const char* colour, const std::string& title) {
    const std::string tip = title.empty() ? "" : "<title>" + xml_escape(title) + "</title>";
    const double r = 4.5;
    switch (k % kShapes) {
    case 0: return fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"{}\" fill=\"{}\">{}</circle>\n", x, y, r, colour, tip);
    case 1:
        return fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{}\" height=\"{}\" fill=\"{}\">{}</rect>\n", x - r, y - r, 2 * r,
                           2 * r, colour, tip);
    case 2:
        return fmt::format("<path d=\"M{:.1f},{:.1f} L{:.1f},{:.1f} L{:.1f},{:.1f} Z\" fill=\"{}\">{}</path>\n", x, y - r - 1, x + r + 1,
                           y + r, x - r - 1, y + r, colour, tip);
    case 3:
        return fmt::format("<path d=\"M{:.1f},{:.1f} L{:.1f},{:.1f} L{:.1f},{:.1f} L{:.1f},{:.1f} Z\" fill=\"{}\">{}</path>\n", x,
                           y - r - 1, x + r + 1, y, x, y + r + 1, x - r - 1, y, colour, tip);
    case 4:
        return fmt::format("<path d=\"M{:.1f},{:.1f} L{:.1f},{:.1f} L{:.1f},{:.1f} Z\" fill=\"white\" stroke=\"{}\" stroke-width=\"2\">{}</path>\n",
                           x, y + r + 1, x + r + 1, y - r, x - r - 1, y - r, colour, tip);
    default:
        return fmt::format("<path d=\"M{:.1f},{:.1f} L{:.1f},{:.1f} M{:.1f},{:.1f} L{:.1f},{:.1f}\" stroke=\"{}\" stroke-width=\"2.5\">{}</path>\n",
                           x - r, y - r, x + r, y + r, x - r, y + r, x + r, y - r, colour, tip);
    }
}

// The x axis: the asked one, else the first swept axis of numbers, else the first swept one.
int chart_axis(const SweepSpec& s) {
    for (int pass = 0; pass < 3; ++pass)
        for (std::size_t i = 0; i < s.axes.size(); ++i) {
            const SweepAxis& a = s.axes[i];
            const bool numeric = std::all_of(a.values.begin(), a.values.end(), [](auto& v) { return integer(v).has_value(); });
            if ((pass == 0 && a.name == s.chart_x) || (pass == 1 && s.chart_x.empty() && a.values.size() > 1 && numeric) ||
                (pass == 2 && s.chart_x.empty() && a.values.size() > 1))
                return static_cast<int>(i);
        }
    return -1;
}

// How a value is written on the axis or in a legend: a file by its stem ("machines/ic-slow.toml":
// ic-slow), a 0 that means "no limit" as "unbounded", long ones cut.
std::string shown(const std::string& axis, const std::string& v) {
    if (sweep_axis_zero_unbounded(axis) && integer(v) == 0) return "unbounded";
    std::string out = v;
    if (v.find('/') != std::string::npos || v.ends_with(".toml") || v.ends_with(".nff"))
        out = std::filesystem::path(v).stem().string();
    if (out.size() > 36) out = out.substr(0, 35) + "...";
    return out;
}

} // namespace

std::string sweep_chart_svg(const SweepSpec& s, const std::vector<SweepCell>& cells, const std::vector<std::string>& texts) {
    const int x = chart_axis(s);
    if (x < 0) return "";
    const std::string y = s.chart_y.empty() ? "cycles.total" : s.chart_y;
    const SweepAxis& xa = s.axes[static_cast<std::size_t>(x)];
    std::vector<std::string> xs = xa.values;
    const bool numeric = std::all_of(xs.begin(), xs.end(), [](auto& v) { return integer(v).has_value(); });
    const bool zero_last = sweep_axis_zero_unbounded(xa.name);
    if (numeric) // ascending, a 0 that means "no limit" last
        std::sort(xs.begin(), xs.end(), [&](auto& a, auto& b) {
            auto rank = [&](const std::string& v) { return std::pair{zero_last && *integer(v) == 0, *integer(v)}; };
            return rank(a) < rank(b);
        });

    // One series per combination of the other swept axes.
    std::map<std::string, std::map<std::string, double>> series;
    std::vector<std::string> order;
    const std::vector<json> docs = parsed(texts);
    double ymax = 0, ymin = std::numeric_limits<double>::infinity(); // ymin: the least positive value
    for (std::size_t c = 0; c < cells.size(); ++c) {
        if (docs[c].is_null()) continue;
        const auto v = sweep_metric(docs[c], y);
        if (!v) continue;
        std::string name;
        for (std::size_t i = 0; i < s.axes.size(); ++i)
            if (static_cast<int>(i) != x && s.axes[i].values.size() > 1)
                name += fmt::format("{}{}={}", name.empty() ? "" : " ", s.axes[i].name, shown(s.axes[i].name, cells[c].values[i]));
        if (!series.count(name)) order.push_back(name);
        series[name][cells[c].values[static_cast<std::size_t>(x)]] = v->get<double>();
        ymax = std::max(ymax, v->get<double>());
        if (v->get<double>() > 0) ymin = std::min(ymin, v->get<double>());
    }
    if (series.empty()) return "";

    // Geometry: the x labels turn when the widest would not fit between two ticks.
    constexpr int kLeft = 90, kTop = 50, kPlotW = 520, kPlotH = 300;
    const std::size_t n = xs.size();
    double widest = 0;
    for (const std::string& v : xs) widest = std::max(widest, kCharWidth * static_cast<double>(shown(xa.name, v).size()));
    const double spacing = numeric ? (n > 1 ? kPlotW / static_cast<double>(n - 1) : kPlotW) : kPlotW / static_cast<double>(n);
    const bool turn = widest > spacing - 8;
    const int label_h = turn ? static_cast<int>(widest * 0.5) + 18 : 18; // sin 30 degrees
    // A series drawn exactly over an earlier one says so in the legend, since it cannot be seen.
    std::vector<std::string> same(order.size());
    for (std::size_t si = 0; si < order.size(); ++si)
        for (std::size_t e = 0; e < si && same[si].empty(); ++e)
            if (series[order[e]] == series[order[si]])
                same[si] = e + 1 == si ? " (the same as above)" : fmt::format(" (the same as line {})", e + 1);
    std::size_t legend_chars = y.size();
    for (std::size_t si = 0; si < order.size(); ++si) legend_chars = std::max(legend_chars, order[si].size() + same[si].size());
    const int legend_w = 60 + static_cast<int>(kCharWidth * static_cast<double>(legend_chars));
    const int width = kLeft + kPlotW + 40 + legend_w;
    const int height = std::max(kTop + kPlotH + label_h + 40, kTop + 30 + 20 * static_cast<int>(order.size()));

    // Linear: from 0 to a round top. Log: from the 1-2-5 tick below the least positive value to
    // the one above the greatest; a value <= 0 has no place on it and is left out.
    const bool span_wide = ymin <= ymax && ymax / ymin >= 30;
    const bool log_y = (s.chart_log_y || (!s.chart_scale_given && span_wide)) && ymin <= ymax;
    const double step = axis_step(ymax), top = std::max(step, std::ceil(ymax / step) * step);
    auto tick_125 = [](double v, bool up) { // the 1-2-5 value at or below (above, when up) v
        const double d = std::pow(10.0, std::floor(std::log10(v)));
        double t = up ? d * 10 : d;
        for (double m : {1.0, 2.0, 5.0, 10.0})
            if (up ? d * m >= v * 0.9999999 && d * m < t : d * m <= v * 1.0000001) t = d * m;
        return t;
    };
    const double lo = log_y ? tick_125(ymin, false) : 0;
    const double hi = log_y ? std::max(lo * 2, tick_125(ymax, true)) : top;
    auto px = [&](std::size_t k) {
        if (!numeric) return kLeft + spacing * (static_cast<double>(k) + 0.5);
        return kLeft + (n == 1 ? kPlotW / 2.0 : spacing * static_cast<double>(k));
    };
    // A categorical axis spreads a category's series across a third of its band.
    const double dodge = numeric || order.size() < 2 ? 0 : std::min(14.0, spacing / 3 / static_cast<double>(order.size() - 1));
    auto py = [&](double v) {
        const double f = log_y ? std::log10(v / lo) / std::log10(hi / lo) : v / top;
        return kTop + kPlotH * (1 - f);
    };
    std::vector<double> ticks;
    if (log_y) {
        for (double d = std::pow(10.0, std::floor(std::log10(lo))); d < hi * 1.0000001; d *= 10)
            for (double m : {1.0, 2.0, 5.0})
                if (d * m >= lo * 0.9999999 && d * m <= hi * 1.0000001) ticks.push_back(d * m);
    } else {
        for (double v = 0; v <= top * 1.0000001; v += step) ticks.push_back(v);
    }

    std::string o = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
                                "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n",
                                width, height);
    o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    const double unit = hi >= 1e6 ? 1e6 : hi >= 1e4 ? 1e3 : 1; // tick labels in millions or thousands
    const char* unit_name = unit == 1e6 ? " (millions)" : unit == 1e3 ? " (thousands)" : "";
    o += fmt::format("<text x=\"{}\" y=\"24\" font-size=\"15\">{}{} against {}{}</text>\n", kLeft, xml_escape(y), unit_name,
                     xml_escape(xa.name),
                     !log_y ? "" : s.chart_log_y ? " (log scale)" : fmt::format(" (log scale: values span {:.0f}x)", ymax / ymin));
    for (const double v : ticks) {
        o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", kLeft, kLeft + kPlotW, py(v), py(v));
        o += fmt::format("<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{:.4g}</text>\n", kLeft - 6, py(v) + 4, v / unit);
    }
    o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" stroke=\"#888\"/>\n", kLeft, kLeft + kPlotW, kTop + kPlotH,
                     kTop + kPlotH);
    for (std::size_t k = 0; k < n; ++k) {
        const std::string label = xml_escape(shown(xa.name, xs[k]));
        if (turn)
            o += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"end\" transform=\"rotate(-30 {:.1f} {})\">{}</text>\n", px(k) + 4,
                             kTop + kPlotH + 16, px(k) + 4, kTop + kPlotH + 16, label);
        else
            o += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", px(k), kTop + kPlotH + 18, label);
        if (!numeric && k > 0) // the bands of a categorical axis
            o += fmt::format("<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{}\" y2=\"{}\" stroke=\"#eee\"/>\n", px(k) - spacing / 2,
                             px(k) - spacing / 2, kTop, kTop + kPlotH);
    }
    o += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", kLeft + kPlotW / 2, kTop + kPlotH + label_h + 22,
                     xml_escape(xa.name));
    for (std::size_t si = 0; si < order.size(); ++si) {
        const auto& pts = series[order[si]];
        const char* colour = kColours[si % std::size(kColours)];
        const char* dash = kDashes[si % std::size(kDashes)];
        const int shape = static_cast<int>(si % kShapes);
        const double dx = dodge * (static_cast<double>(si) - static_cast<double>(order.size() - 1) / 2);
        std::string path, marks;
        for (std::size_t k = 0; k < n; ++k) {
            const auto it = pts.find(xs[k]);
            if (it == pts.end() || (log_y && it->second <= 0)) continue;
            const double cx = px(k) + dx, cy = py(it->second);
            path += fmt::format("{}{:.1f},{:.1f}", path.empty() ? "M" : " L", cx, cy);
            marks += marker(shape, cx, cy, colour,
                            fmt::format("{}{}: {}", order[si].empty() ? "" : order[si] + " ", shown(xa.name, xs[k]), it->second));
        }
        if (numeric)
            o += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{}/>\n", path, colour,
                             *dash ? fmt::format(" stroke-dasharray=\"{}\"", dash) : "");
        o += marks;
        const int lx = kLeft + kPlotW + 30, ly = kTop + 14 + 20 * static_cast<int>(si);
        if (numeric)
            o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"2\"{}/>\n", lx, lx + 28, ly - 4,
                             ly - 4, colour, *dash ? fmt::format(" stroke-dasharray=\"{}\"", dash) : "");
        o += marker(shape, lx + 14, ly - 4, colour, "");
        o += fmt::format("<text x=\"{}\" y=\"{}\">{}{}</text>\n", lx + 36, ly, xml_escape(order[si].empty() ? y : order[si]),
                         same[si]);
    }
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::paper
