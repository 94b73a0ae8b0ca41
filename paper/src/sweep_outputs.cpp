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

using nlohmann::json;

std::optional<long long> integer(const std::string& v) {
    long long x = 0;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size() || v.empty()) return std::nullopt;
    return x;
}

std::vector<json> parsed(const std::vector<std::string>& texts) {
    std::vector<json> out;
    for (const std::string& t : texts) out.push_back(t.empty() ? json() : json::parse(t));
    return out;
}

namespace {

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

} // namespace nesshi::paper
