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

// What a run is, as text: its scene, model, image size, grid, stage machines and options.
std::string config(const json& j, const std::string& key) {
    auto text = [](const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); };
    if (key == "size" && j.contains("size") && j["size"].is_array() && j["size"].size() == 2)
        return fmt::format("{}x{}", text(j["size"][0]), text(j["size"][1]));
    if (key == "grid" && j.contains("grid") && j["grid"].contains("n") && j["grid"]["n"].is_array()) {
        std::string g;
        for (const json& n : j["grid"]["n"]) g += (g.empty() ? "" : "x") + text(n);
        return g;
    }
    if (key == "os_machine" || key == "ic_machine") {
        const char* st = key == "os_machine" ? "os" : "ic";
        if (j.contains("detail") && j["detail"].contains(st) && j["detail"][st].contains("machine"))
            return text(j["detail"][st]["machine"]);
        return "";
    }
    if (j.contains("machine") && j["machine"].is_object() && j["machine"].contains(key)) return text(j["machine"][key]);
    return j.contains(key) ? text(j[key]) : "";
}
constexpr const char* kConfigKeys[] = {"scene", "model", "size", "grid", "max_depth", "epsilon", "os_machine", "ic_machine",
                                       "pes", "balance", "window", "fifo_capacity", "fifo_latency", "quantum", "cache"};

std::string format_value(double v, bool ratio_like) {
    if (ratio_like) return fmt::format("{:.3f}", v);
    return fmt::format("{:.0f}", v);
}

} // namespace

Comparison compare_runs(const std::vector<std::pair<std::string, std::string>>& runs) {
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
    Comparison c;
    Table& t = c.table;
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
    // What each run is; the ratio columns say whether it is the first run's.
    for (const char* key : kConfigKeys) {
        std::vector<std::string> r = {fmt::format("run.{}", key)};
        bool any = false;
        for (const json& d : docs) {
            r.push_back(config(d, key));
            any |= !r.back().empty();
        }
        if (!any) continue;
        bool differs = false;
        for (std::size_t i = 2; i <= docs.size(); ++i) {
            differs |= r[i] != r[1];
            r.push_back(r[i] == r[1] ? "same" : "differs");
        }
        for (std::size_t i = 1; i <= docs.size(); ++i)
            if (r[i].empty()) r[i] = "—";
        if (differs && (std::string(key) == "scene" || std::string(key) == "size"))
            c.warnings.push_back(fmt::format("the runs are of different {}s ({}): their cycles do not compare", key,
                                             fmt::join(r.begin() + 1, r.begin() + static_cast<std::ptrdiff_t>(docs.size()) + 1, ", ")));
        t.rows.push_back(std::move(r));
    }
    row("cycles.total", false, [](const json& d) { return at(d, {"cycles", "total"}); });
    for (const char* st : {"os", "ic", "sc"}) {
        for (const char* k : {"processing", "communication", "wait"})
            row(fmt::format("cycles.{}.{}", st, k), false, [&](const json& d) { return at(d, {"cycles", st, k}); });
        for (const char* k : {"ilp", "utilization"})
            row(fmt::format("cycles.{}.{}", st, k), true, [&](const json& d) { return at(d, {"cycles", st, k}); });
    }
    row("machine.cache.misses", false, [](const json& d) { return at(d, {"machine", "cache", "misses"}); });
    row("machine.max_fifo_words", false, [](const json& d) { return at(d, {"machine", "max_fifo_words"}); });
    // Each kernel region, in the first run's order, then any the others add. A region's cycles
    // compare only between runs of the same kernel: when the runs' labels differ (another kernel,
    // or one rescheduled for another machine, whose loop is __sa_kernel and its glue elsewhere), a
    // label's cycles cover different code, so no region ratio is given.
    for (const char* st : {"os", "ic"}) {
        std::vector<std::string> labels;
        std::vector<std::vector<std::string>> per_run;
        for (const json& d : docs) {
            per_run.emplace_back();
            if (d.contains("detail") && d["detail"].contains(st))
                for (const json& r : d["detail"][st].value("regions", json::array())) {
                    const std::string l = r.value("label", "");
                    per_run.back().push_back(l);
                    if (std::find(labels.begin(), labels.end(), l) == labels.end()) labels.push_back(l);
                }
        }
        const std::size_t first = t.rows.size();
        for (const std::string& l : labels)
            row(fmt::format("detail.{}.regions.{}.cycles", st, l), false,
                [&](const json& d) { return region_cycles(d, st, l); });
        for (std::size_t i = 1; i < docs.size(); ++i) {
            if (per_run[i] == per_run[0] || per_run[i].empty() || per_run[0].empty()) continue;
            for (std::size_t k = first; k < t.rows.size(); ++k) t.rows[k][docs.size() + i] = "—";
            t.notes.push_back(fmt::format("{}'s {} kernel has other regions than {}'s (another kernel, or one scheduled for "
                                          "its machine): its region cycles are shown but not divided; compare the stage's "
                                          "processing cycles.",
                                          runs[i].first, st, runs[0].first));
        }
    }
    t.notes.push_back("Ratios are each run's value over the first run's; — where a run has no such figure.");
    for (const std::string& w : c.warnings) t.notes.push_back("Warning: " + w + ".");
    return c;
}

} // namespace nesshi::paper
