// The sweep spec: parsing, checking, the cells it asks for and the run each cell stands for.
#include "paper/sweep.hpp"

#include "base/hash.hpp"
#include "base/read_file.hpp"
#include "kernels/abi.hpp"
#include "rt/grid.hpp"
#include "rt/render.hpp"
#include "rt/scene.hpp"
#include "sweep_metric.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <limits>

namespace nesshi::paper {

namespace {

base::SourceLoc where(const std::string& file, const toml::source_region& r) {
    return base::SourceLoc(file, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column));
}

bool machine_axis(const std::string& axis) { return axis == "os_machine" || axis == "ic_machine" || axis == "seq_machine"; }

// A value of a file axis that names a file (not a preset or a built-in scene), relative to the
// spec's folder as an include would be: the spec runs the same from any working directory.
std::string from_spec_folder(const std::string& axis, const std::string& value, const std::string& spec_file) {
    const bool file_axis = machine_axis(axis) || axis == "kernels" || axis == "scene";
    if (!file_axis || value.empty() || value[0] == '/') return value;
    const bool named = axis == "scene" ? value.find('/') == std::string::npos && value.find(".nff") == std::string::npos
                                       : axis != "kernels" && value.find('/') == std::string::npos &&
                                             !value.ends_with(".toml");
    if (named) return value;
    const std::filesystem::path folder = std::filesystem::path(spec_file).parent_path();
    return folder.empty() ? value : (folder / value).lexically_normal().string();
}

// A machine axis's value, loaded (a description that does not load is the spec's error).
kbuild::StageMachine load_stage_machine(const std::string& axis, const std::string& value) {
    try {
        return kbuild::StageMachine(value);
    } catch (const std::exception& e) {
        throw PaperError(fmt::format("{} = {}: {}", axis, value, e.what()));
    }
}

// A cell's machine: the spec's, loaded when it was read (a spec built in code loads it here).
kbuild::StageMachine stage_machine(const SweepSpec& s, const std::string& axis, const std::string& value) {
    if (const auto it = s.machines.find(value); it != s.machines.end()) return it->second;
    return load_stage_machine(axis, value);
}

bool is_axis(const std::string& name) {
    const auto& a = sweep_axis_names();
    return std::any_of(a.begin(), a.end(), [&](const auto& p) { return p.first == name; });
}

// A scalar in its TOML spelling; nullopt for tables, arrays, floats and dates.
std::optional<std::string> scalar(const toml::node& n) {
    if (const auto* s = n.as_string()) return s->get();
    if (const auto* i = n.as_integer()) return std::to_string(i->get());
    if (const auto* b = n.as_boolean()) return std::string(b->get() ? "true" : "false");
    return std::nullopt;
}

std::vector<std::string> strings(const toml::node& n, const std::string& file, const char* key) {
    std::vector<std::string> out;
    const toml::array* a = n.as_array();
    if (!a) throw PaperError(where(file, n.source()), fmt::format("'{}' must be a list of strings", key));
    for (const toml::node& e : *a) {
        const auto* s = e.as_string();
        if (!s) throw PaperError(where(file, e.source()), fmt::format("'{}' must be a list of strings", key));
        out.push_back(s->get());
    }
    return out;
}

template <class T>
T number(const std::string& axis, const std::string& v, T lo, T hi) {
    T x{};
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size() || x < lo || x > hi)
        throw PaperError(fmt::format("{} = {}: must be a whole number from {} to {}", axis, v, lo, hi));
    return x;
}

bool boolean(const std::string& axis, const std::string& v) {
    if (v == "true") return true;
    if (v == "false") return false;
    throw PaperError(fmt::format("{} = {}: must be true or false", axis, v));
}

} // namespace

const std::vector<std::pair<std::string, std::string>>& sweep_axis_names() {
    static const std::vector<std::pair<std::string, std::string>> k = {
        {"scene", "SPD name, NAME:SIZE or NFF file (default balls)"},
        {"size", "image size N x N (default 512)"},
        {"grid", "voxels per side (default: the cost model's choice)"},
        {"model", "S, M or V (default V)"},
        {"pes", "processing elements (default 1)"},
        {"balance", "interleaved or dynamic"},
        {"epoch", "dynamic balance epoch, cycles"},
        {"window", "eye rays in flight per PE"},
        {"ray_slots", "rays in flight per PE (default: capacity / 12 with bounded FIFOs)"},
        {"fifo_capacity", "words per FIFO (0 = unbounded)"},
        {"fifo_latency", "extra cycles from a send to its receive"},
        {"quantum", "host switching of a PE's stages (no result depends on it)"},
        {"cache", "IC cache over global memory (true/false; any cache_* axis turns it on)"},
        {"cache_size", "IC cache bytes"},
        {"cache_ways", "IC cache ways"},
        {"cache_line", "IC cache line bytes"},
        {"miss_cycles", "IC cache miss penalty"},
        {"resident", "IC data in resident memory when it fits (true/false)"},
        {"os_machine", "machine of the OS stage: preset or TOML"},
        {"ic_machine", "machine of the IC stage: preset or TOML"},
        {"seq_machine", "machine of models S and M, and SC prices"},
        {"kernels", "kernel source folder"},
        {"max_cycles", "cycle limit per PE: a cell past it fails alone (default 2,000,000 per pixel)"},
    };
    return k;
}

bool sweep_axis_zero_unbounded(std::string_view axis) { return axis == "fifo_capacity"; }

const std::vector<std::string>& default_sweep_metrics() {
    static const std::vector<std::string> k = {
        "cycles.total",          "cycles.os.processing", "cycles.os.communication", "cycles.os.wait",
        "cycles.ic.processing",  "cycles.ic.communication", "cycles.ic.wait",      "cycles.sc.processing",
        "cycles.sc.communication", "cycles.sc.wait",     "cycles.os.ilp",           "cycles.os.utilization",
        "cycles.ic.ilp",         "cycles.ic.utilization", "machine.max_fifo_words", "machine.cache.misses",
        "host.wall_seconds"};
    return k;
}

const nlohmann::json& sweep_metric_schema() {
    static const nlohmann::json schema = [] {
        const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 2);
        rt::RenderOptions ro;
        ro.width = ro.height = 1;
        machine::Options mo;
        mo.cache.enabled = true;
        mo.dynamic_balance = true;
        mo.ray_slots = 1;
        machine::Result r;
        r.machine.s_cycles = 1;
        r.machine.os_kernel.scheduled = true;
        return machine::stats_json(prep, ro, mo, r);
    }();
    return schema;
}


namespace {

// Every metric names a number some cell's stats JSON has: a typo is an error at its line, not an
// empty column.
void check_metric_paths(const SweepSpec& s, const toml::table& t, const std::string& file) {
    const toml::array* listed = t["metrics"].as_array();
    for (std::size_t i = 0; i < s.metrics.size(); ++i) {
        const std::string& m = s.metrics[i];
        if (sweep_metric(sweep_metric_schema(), m)) continue;
        const toml::node* at = listed && i < listed->size() ? listed->get(i) : t["chart"]["y"].node();
        throw PaperError(at ? where(file, at->source()) : base::SourceLoc(file),
                         fmt::format("unknown metric '{}': no number of the stats JSON is there (a dotted path such as "
                                     "cycles.os.processing; `nesshi render --stats-json` shows them all)", m));
    }
}

} // namespace

SweepSpec parse_sweep_spec(const std::string& text, const std::string& file) {
    toml::table t;
    try {
        t = toml::parse(text, file);
    } catch (const toml::parse_error& e) {
        throw PaperError(where(file, e.source()), std::string(e.description()));
    }
    SweepSpec s;
    s.file = file;
    for (const auto& [key, node] : t) {
        const std::string k(key.str());
        if (k == "metrics") {
            s.metrics = strings(node, file, "metrics");
        } else if (k == "axes") {
            const toml::table* axes = node.as_table();
            if (!axes) throw PaperError(where(file, node.source()), "'axes' must be a table");
            for (const auto& [name, value] : *axes) {
                SweepAxis a{std::string(name.str()), {}};
                if (!is_axis(a.name))
                    throw PaperError(where(file, name.source()),
                                     fmt::format("unknown axis '{}' (nesshi sweep --help lists them)", a.name));
                auto add = [&](const toml::node& v) {
                    auto x = scalar(v);
                    if (x) x = from_spec_folder(a.name, *x, file);
                    if (!x) throw PaperError(where(file, v.source()), fmt::format("{}: a value must be a string, a whole number or a boolean", a.name));
                    if (std::find(a.values.begin(), a.values.end(), *x) != a.values.end()) // one cell, one file: twice would clash
                        throw PaperError(where(file, v.source()), fmt::format("{}: {} is listed twice", a.name, *x));
                    if (machine_axis(a.name) && !s.machines.count(*x)) try {
                            s.machines.emplace(*x, load_stage_machine(a.name, *x));
                        } catch (const PaperError& e) {
                            throw PaperError(where(file, v.source()), e.message());
                        }
                    a.values.push_back(*x);
                };
                if (const toml::array* list = value.as_array()) {
                    if (list->empty()) throw PaperError(where(file, value.source()), fmt::format("{}: empty list", a.name));
                    for (const toml::node& v : *list) add(v);
                } else {
                    add(value);
                }
                s.axes.push_back(std::move(a));
            }
        } else if (k == "chart") {
            const toml::table* c = node.as_table();
            if (!c) throw PaperError(where(file, node.source()), "'chart' must be a table");
            for (const auto& [ck, cv] : *c) {
                const std::string name(ck.str());
                const auto* v = cv.as_string();
                if ((name != "x" && name != "y" && name != "y_scale") || !v)
                    throw PaperError(where(file, cv.source()),
                                     "chart takes x = \"AXIS\", y = \"METRIC\" and y_scale = \"linear\" or \"log\"");
                if (name == "y_scale") {
                    if (v->get() != "linear" && v->get() != "log")
                        throw PaperError(where(file, cv.source()), "chart y_scale is \"linear\" or \"log\"");
                    s.chart_log_y = v->get() == "log";
                    s.chart_scale_given = true;
                } else {
                    (name == "x" ? s.chart_x : s.chart_y) = v->get();
                }
            }
        } else {
            throw PaperError(where(file, key.source()),
                             fmt::format("unknown key '{}' (a spec has metrics, [axes] and [chart])", k));
        }
    }
    if (s.axes.empty()) throw PaperError(base::SourceLoc(file), "no [axes]: nothing to sweep");
    // toml++ iterates keys sorted; the columns and the cell order follow the file instead.
    std::stable_sort(s.axes.begin(), s.axes.end(), [&](const SweepAxis& a, const SweepAxis& b) {
        return t["axes"][a.name].node()->source().begin < t["axes"][b.name].node()->source().begin;
    });
    if (s.metrics.empty()) s.metrics = default_sweep_metrics();
    if (!s.chart_x.empty() &&
        std::none_of(s.axes.begin(), s.axes.end(), [&](const SweepAxis& a) { return a.name == s.chart_x; }))
        throw PaperError(base::SourceLoc(file), fmt::format("chart x '{}' is not one of the spec's axes", s.chart_x));
    if (!s.chart_y.empty() && std::find(s.metrics.begin(), s.metrics.end(), s.chart_y) == s.metrics.end())
        s.metrics.push_back(s.chart_y);
    // Every value checked before anything runs, each alone (the other axes at their first value):
    // a value's meaning does not depend on the other axes, and the product may be huge.
    for (std::size_t i = 0; i < s.axes.size(); ++i)
        for (const std::string& v : s.axes[i].values) {
            SweepCell c;
            for (const SweepAxis& a : s.axes) c.values.push_back(a.values.front());
            c.values[i] = v;
            try {
                (void)sweep_inputs(s, c);
            } catch (const PaperError& e) {
                throw PaperError(where(file, t["axes"][s.axes[i].name].node()->source()), e.message());
            }
        }
    // As `nesshi render` refuses them: axes that change nothing on model S (one processor runs the
    // three stages on one clock), where a cell has model S.
    const auto model = std::find_if(s.axes.begin(), s.axes.end(), [](const SweepAxis& a) { return a.name == "model"; });
    if (model != s.axes.end() && std::find(model->values.begin(), model->values.end(), "S") != model->values.end())
        for (const SweepAxis& a : s.axes)
            if (a.name == "fifo_latency" || a.name == "quantum")
                throw PaperError(where(file, t["axes"][a.name].node()->source()),
                                 fmt::format("{} has no effect on model S (one processor runs the three stages on one "
                                             "clock): drop the axis, or sweep models M and V only",
                                             a.name));
    check_metric_paths(s, t, file);
    return s;
}

SweepSpec load_sweep_spec(const std::string& file) { return parse_sweep_spec(base::read_file(file), file); }

std::size_t sweep_cell_count(const SweepSpec& s) {
    std::size_t n = 1;
    for (const SweepAxis& a : s.axes)
        n = a.values.size() && n > std::numeric_limits<std::size_t>::max() / a.values.size() ? std::numeric_limits<std::size_t>::max()
                                                                                              : n * a.values.size();
    return n;
}

std::string sweep_product(const SweepSpec& s) {
    std::vector<std::string> f;
    for (const SweepAxis& a : s.axes)
        if (a.values.size() > 1) f.push_back(fmt::format("{} {}", a.name, a.values.size()));
    return f.empty() ? std::string("one value per axis") : fmt::format("{}", fmt::join(f, " x "));
}

std::vector<SweepCell> sweep_cells(const SweepSpec& s) {
    std::vector<SweepCell> cells{SweepCell{}};
    for (const SweepAxis& a : s.axes) {
        std::vector<SweepCell> next;
        for (const SweepCell& c : cells)
            for (const std::string& v : a.values) {
                SweepCell d = c;
                d.values.push_back(v);
                next.push_back(std::move(d));
            }
        cells = std::move(next);
    }
    for (SweepCell& c : cells) {
        base::Fnv1a h;
        for (std::size_t i = 0; i < s.axes.size(); ++i) h.add(s.axes[i].name).add("=").add(c.values[i]).add(";");
        c.id = base::hex64(h.value());
    }
    return cells;
}

SweepRunInputs sweep_inputs(const SweepSpec& s, const SweepCell& c) {
    SweepRunInputs in;
    in.render.width = in.render.height = 512;
    in.render.threads = 1;
    in.machine.threads = 1; // cells run concurrently instead
    bool slots_named = false, window_named = false, limit_named = false;
    for (std::size_t i = 0; i < s.axes.size(); ++i) {
        const std::string& a = s.axes[i].name;
        const std::string& v = c.values[i];
        machine::Options& mo = in.machine;
        if (a == "scene") in.scene = v;
        else if (a == "size") in.render.width = in.render.height = number<int>(a, v, 1, 16384);
        else if (a == "grid") in.grid = number<int>(a, v, 1, rt::kMaxGridResolution);
        else if (a == "model") {
            if (!machine::parse_model(v, mo.model)) throw PaperError(fmt::format("model = {}: must be S, M or V", v));
        } else if (a == "pes") mo.pes = number<int>(a, v, 1, 64);
        else if (a == "balance") {
            if (v != "interleaved" && v != "dynamic")
                throw PaperError(fmt::format("balance = {}: must be interleaved or dynamic", v));
            mo.dynamic_balance = v == "dynamic";
        } else if (a == "epoch") mo.epoch = number<std::uint64_t>(a, v, 1, 1u << 30);
        else if (a == "window") { mo.window = number<int>(a, v, 1, 4096); window_named = true; }
        else if (a == "ray_slots") { mo.ray_slots = number<int>(a, v, 1, static_cast<int>(kernels::abi::kOsSlots)); slots_named = true; }
        else if (a == "fifo_capacity") mo.fifo_capacity = number<std::size_t>(a, v, 0, 1u << 24);
        else if (a == "fifo_latency") mo.fifo_latency = number<std::uint32_t>(a, v, 0, 1u << 20);
        else if (a == "quantum") mo.quantum = number<std::uint64_t>(a, v, 1, 1u << 20);
        else if (a == "cache") mo.cache.enabled = boolean(a, v);
        else if (a == "cache_size") mo.cache.bytes = number<std::uint32_t>(a, v, 64, 1u << 30);
        else if (a == "cache_ways") mo.cache.ways = number<std::uint32_t>(a, v, 1, 64);
        else if (a == "cache_line") mo.cache.line = number<std::uint32_t>(a, v, 4, 4096);
        else if (a == "miss_cycles") mo.cache.miss_cycles = number<std::uint32_t>(a, v, 0, 1u << 20);
        else if (a == "resident") mo.resident = boolean(a, v);
        else if (a == "os_machine") mo.os_machine = stage_machine(s, a, v);
        else if (a == "ic_machine") mo.ic_machine = stage_machine(s, a, v);
        else if (a == "seq_machine") mo.seq_machine = stage_machine(s, a, v);
        else if (a == "kernels") mo.kernels_dir = v;
        else if (a == "max_cycles") { mo.max_cycles = number<std::uint64_t>(a, v, 1, std::uint64_t{1} << 62); limit_named = true; }
    }
    if (!limit_named)
        in.machine.max_cycles = kSweepCyclesPerPixel * static_cast<std::uint64_t>(in.render.width) *
                                static_cast<std::uint64_t>(in.render.height);
    // Any cache_* axis means a cache, unless `cache = false` says otherwise.
    const bool cache_axes = std::any_of(s.axes.begin(), s.axes.end(), [](const SweepAxis& x) {
        return x.name.rfind("cache_", 0) == 0 || x.name == "miss_cycles";
    });
    const bool cache_flag = std::any_of(s.axes.begin(), s.axes.end(), [](const SweepAxis& x) { return x.name == "cache"; });
    if (cache_axes && !cache_flag) in.machine.cache.enabled = true;
    // As `nesshi render` does: bounded FIFOs without a window or ray-slot limit get the rays in
    // flight with which no FIFO can fill.
    if (in.machine.fifo_capacity > 0 && !slots_named && !window_named)
        in.machine.ray_slots = machine::deadlock_free_ray_slots(in.machine.fifo_capacity);
    return in;
}

} // namespace nesshi::paper
