// A sweep's outputs: the tidy table (CSV and JSON lines: every axis, then every metric) and the
// chart of one metric against one axis.
#include "paper/sweep.hpp"

#include "report_format.hpp"
#include "sweep_metric.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace nesshi::paper {

namespace {

using nlohmann::json;

std::optional<long long> integer(const std::string& v) {
    long long x = 0;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size() || v.empty()) return std::nullopt;
    return x;
}

// An axis value typed as the spec wrote it: a whole number, a boolean, else a string.
json typed(const std::string& v) {
    if (const auto i = integer(v)) return *i;
    if (v == "true" || v == "false") return v == "true";
    return v;
}

std::string csv_field(const std::string& v) {
    if (v.find_first_of(",\"\n") == std::string::npos) return v;
    std::string o = "\"";
    for (char c : v) o += c == '"' ? std::string("\"\"") : std::string(1, c);
    return o + "\"";
}

std::vector<json> parsed(const std::vector<std::string>& texts) {
    std::vector<json> out;
    for (const std::string& t : texts) out.push_back(t.empty() ? json() : json::parse(t));
    return out;
}

} // namespace

std::optional<json> sweep_metric(const json& doc, const std::string& path) {
    const json* j = &doc;
    for (std::size_t start = 0;;) {
        const std::size_t dot = path.find('.', start);
        const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (!j->is_object() || !j->contains(key)) return std::nullopt;
        j = &j->at(key);
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    if (!j->is_number()) return std::nullopt;
    return *j;
}

std::string sweep_csv(const SweepSpec& s, const std::vector<SweepCell>& cells, const std::vector<std::string>& texts) {
    std::vector<std::string> header = {"cell"};
    for (const SweepAxis& a : s.axes) header.push_back(a.name);
    header.insert(header.end(), s.metrics.begin(), s.metrics.end());
    std::string o;
    auto line = [&](const std::vector<std::string>& f) {
        for (std::size_t i = 0; i < f.size(); ++i) o += (i ? "," : "") + csv_field(f[i]);
        o += "\n";
    };
    line(header);
    const std::vector<json> docs = parsed(texts);
    for (std::size_t c = 0; c < cells.size(); ++c) {
        if (docs[c].is_null()) continue;
        std::vector<std::string> row = {cells[c].id};
        row.insert(row.end(), cells[c].values.begin(), cells[c].values.end());
        for (const std::string& m : s.metrics) {
            const auto v = sweep_metric(docs[c], m);
            row.push_back(v ? v->dump() : "");
        }
        line(row);
    }
    return o;
}

std::vector<std::string> sweep_jsonl(const SweepSpec& s, const std::vector<SweepCell>& cells,
                                     const std::vector<std::string>& texts) {
    std::vector<std::string> rows;
    const std::vector<json> docs = parsed(texts);
    for (std::size_t c = 0; c < cells.size(); ++c) {
        if (docs[c].is_null()) continue;
        nlohmann::ordered_json row = nlohmann::ordered_json::object();
        row["cell"] = cells[c].id;
        for (std::size_t i = 0; i < s.axes.size(); ++i) row[s.axes[i].name] = typed(cells[c].values[i]);
        for (const std::string& m : s.metrics) row[m] = sweep_metric(docs[c], m).value_or(json());
        rows.push_back(row.dump());
    }
    return rows;
}

std::string sweep_chart_svg(const SweepSpec& s, const std::vector<SweepCell>& cells,
                            const std::vector<std::string>& texts) {
    // x: the asked axis, else the first swept axis whose values are all numbers, else the first swept one.
    int x = -1;
    for (int pass = 0; pass < 3 && x < 0; ++pass)
        for (std::size_t i = 0; i < s.axes.size() && x < 0; ++i) {
            const SweepAxis& a = s.axes[i];
            const bool numeric = std::all_of(a.values.begin(), a.values.end(), [](auto& v) { return integer(v).has_value(); });
            if ((pass == 0 && a.name == s.chart_x) || (pass == 1 && s.chart_x.empty() && a.values.size() > 1 && numeric) ||
                (pass == 2 && s.chart_x.empty() && a.values.size() > 1))
                x = static_cast<int>(i);
        }
    if (x < 0) return "";
    const std::string y = s.chart_y.empty() ? "cycles.total" : s.chart_y;
    const SweepAxis& xa = s.axes[static_cast<std::size_t>(x)];
    // In ascending order when numeric (a 0 that means "no limit" last), else as written.
    std::vector<std::string> xs = xa.values;
    const bool zero_last = sweep_axis_zero_unbounded(xa.name);
    auto label = [&](const std::string& v) { return zero_last && integer(v) == 0 ? std::string("unbounded") : v; };
    if (std::all_of(xs.begin(), xs.end(), [](auto& v) { return integer(v).has_value(); }))
        std::sort(xs.begin(), xs.end(), [&](auto& a, auto& b) {
            auto rank = [&](const std::string& v) {
                const auto n = *integer(v);
                return std::pair{zero_last && n == 0, n};
            };
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
                name += fmt::format("{}{}={}", name.empty() ? "" : " ", s.axes[i].name, cells[c].values[i]);
        if (!series.count(name)) order.push_back(name);
        series[name][cells[c].values[static_cast<std::size_t>(x)]] = v->get<double>();
        ymax = std::max(ymax, v->get<double>());
        if (v->get<double>() > 0) ymin = std::min(ymin, v->get<double>());
    }
    if (series.empty()) return "";

    static constexpr const char* kColors[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                              "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
    constexpr int kLeft = 90, kTop = 50, kPlotW = 520, kPlotH = 300, kLegendW = 260;
    const int height = kTop + kPlotH + 60;
    // Linear: from 0 to a round top. Log (y_scale = "log"): from the 1-2-5 tick below the least
    // positive value to the one above the greatest; a value <= 0 has no place on it and is left out.
    const bool log_y = s.chart_log_y && ymin <= ymax;
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
    auto px = [&](std::size_t k) { return kLeft + (xs.size() == 1 ? kPlotW / 2.0 : kPlotW * static_cast<double>(k) / static_cast<double>(xs.size() - 1)); };
    auto py = [&](double v) {
        const double f = log_y ? std::log10(v / lo) / std::log10(hi / lo) : v / top;
        return kTop + kPlotH * (1 - f);
    };
    auto drawn = [&](double v) { return !log_y || v > 0; };
    std::vector<double> ticks;
    if (log_y) {
        for (double d = std::pow(10.0, std::floor(std::log10(lo))); d < hi * 1.0000001; d *= 10)
            for (double m : {1.0, 2.0, 5.0})
                if (d * m >= lo * 0.9999999 && d * m <= hi * 1.0000001) ticks.push_back(d * m);
    } else {
        for (double v = 0; v <= top * 1.0000001; v += step) ticks.push_back(v);
    }
    std::string o = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
                                "font-family=\"sans-serif\" font-size=\"12\">\n",
                                kLeft + kPlotW + 40 + kLegendW, height);
    o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    // Tick labels in millions or thousands when the values are that large.
    const double unit = hi >= 1e6 ? 1e6 : hi >= 1e4 ? 1e3 : 1;
    const char* unit_name = unit == 1e6 ? " (millions)" : unit == 1e3 ? " (thousands)" : "";
    o += fmt::format("<text x=\"{}\" y=\"24\" font-size=\"15\">{}{} against {}{}</text>\n", kLeft, xml_escape(y),
                     unit_name, xml_escape(xa.name), log_y ? " (log scale)" : "");
    for (const double v : ticks) {
        o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>\n", kLeft, kLeft + kPlotW,
                         py(v), py(v));
        o += fmt::format("<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{:.4g}</text>\n", kLeft - 6, py(v) + 4, v / unit);
    }
    for (std::size_t k = 0; k < xs.size(); ++k)
        o += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", px(k), kTop + kPlotH + 18,
                         xml_escape(label(xs[k])));
    o += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", kLeft + kPlotW / 2,
                     kTop + kPlotH + 40, xml_escape(xa.name));
    for (std::size_t si = 0; si < order.size(); ++si) {
        const auto& pts = series[order[si]];
        const char* color = kColors[si % std::size(kColors)];
        std::string path;
        for (std::size_t k = 0; k < xs.size(); ++k) {
            const auto it = pts.find(xs[k]);
            if (it == pts.end() || !drawn(it->second)) continue;
            path += fmt::format("{}{:.1f},{:.1f}", path.empty() ? "M" : " L", px(k), py(it->second));
            o += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"><title>{}: {}</title></circle>\n",
                             px(k), py(it->second), color, xml_escape(order[si].empty() ? label(xs[k]) : order[si] + " " + label(xs[k])),
                             it->second);
        }
        o += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n", path, color);
        const int ly = kTop + 14 + 18 * static_cast<int>(si);
        o += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"{}\"/>\n", kLeft + kPlotW + 30, ly - 10, color);
        o += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", kLeft + kPlotW + 48, ly,
                         xml_escape(order[si].empty() ? y : order[si]));
    }
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::paper
