// Machine runs side by side (paper/compare.hpp).
#include "paper/compare.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace nesshi::paper {

namespace {

using nlohmann::json;

std::optional<double> at(const json& j, std::initializer_list<const char*> path) {
    const json* p = &j;
    for (const char* k : path) {
        if (!p->is_object() || !p->contains(k)) return std::nullopt;
        p = &p->at(k);
    }
    if (!p->is_number()) return std::nullopt;
    return p->get<double>();
}

// A region's cycles in a stage's detail, by label.
std::optional<double> region_cycles(const json& j, const char* stage, const std::string& label) {
    if (!j.contains("detail") || !j["detail"].contains(stage)) return std::nullopt;
    for (const json& r : j["detail"][stage].value("regions", json::array()))
        if (r.value("label", "") == label && r.contains("cycles")) return r["cycles"].get<double>();
    return std::nullopt;
}

std::string format_value(double v, bool ratio_like) {
    if (ratio_like) return fmt::format("{:.3f}", v);
    return fmt::format("{:.0f}", v);
}

} // namespace

Table compare_runs(const std::vector<std::pair<std::string, std::string>>& runs) {
    if (runs.size() < 2) throw PaperError("compare needs two runs or more");
    std::vector<json> docs;
    for (const auto& [name, text] : runs) {
        json j;
        try {
            j = json::parse(text);
        } catch (const json::exception& e) {
            throw PaperError(base::SourceLoc(name), fmt::format("not JSON: {}", e.what()));
        }
        if (!at(j, {"cycles", "total"}))
            throw PaperError(base::SourceLoc(name), "not a machine run's stats JSON (no cycles.total; render with --model S, M or V)");
        docs.push_back(std::move(j));
    }
    Table t;
    t.title = "Runs compared";
    t.header = {"metric"};
    for (const auto& r : runs) t.header.push_back(r.first);
    for (std::size_t i = 1; i < runs.size(); ++i) t.header.push_back(fmt::format("{} / {}", runs[i].first, runs[0].first));

    auto row = [&](const std::string& name, bool ratio_like, auto value_of) {
        std::vector<std::optional<double>> v;
        for (const json& d : docs) v.push_back(value_of(d));
        if (std::none_of(v.begin(), v.end(), [](auto& x) { return x.has_value(); })) return;
        std::vector<std::string> r = {name};
        for (const auto& x : v) r.push_back(x ? format_value(*x, ratio_like) : "—");
        for (std::size_t i = 1; i < v.size(); ++i)
            r.push_back(v[0] && v[i] && *v[0] != 0 ? fmt::format("{:.3f}", *v[i] / *v[0]) : "—");
        t.rows.push_back(std::move(r));
    };
    row("cycles.total", false, [](const json& d) { return at(d, {"cycles", "total"}); });
    for (const char* st : {"os", "ic", "sc"}) {
        for (const char* k : {"processing", "communication", "wait"})
            row(fmt::format("cycles.{}.{}", st, k), false, [&](const json& d) { return at(d, {"cycles", st, k}); });
        for (const char* k : {"ilp", "utilization"})
            row(fmt::format("cycles.{}.{}", st, k), true, [&](const json& d) { return at(d, {"cycles", st, k}); });
    }
    row("machine.cache.misses", false, [](const json& d) { return at(d, {"machine", "cache", "misses"}); });
    row("machine.max_fifo_words", false, [](const json& d) { return at(d, {"machine", "max_fifo_words"}); });
    // Each kernel region, in the first run's order, then any the others add.
    for (const char* st : {"os", "ic"}) {
        std::vector<std::string> labels;
        for (const json& d : docs)
            if (d.contains("detail") && d["detail"].contains(st))
                for (const json& r : d["detail"][st].value("regions", json::array()))
                    if (const std::string l = r.value("label", ""); std::find(labels.begin(), labels.end(), l) == labels.end())
                        labels.push_back(l);
        for (const std::string& l : labels)
            row(fmt::format("detail.{}.regions.{}.cycles", st, l), false,
                [&](const json& d) { return region_cycles(d, st, l); });
    }
    t.notes.push_back("Ratios are each run's value over the first run's; — where a run has no such figure.");
    return t;
}

} // namespace nesshi::paper
