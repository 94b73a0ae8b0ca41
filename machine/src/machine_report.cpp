// Machine reports: stats JSON (render's keys plus "cycles" and "host"), the terminal summary and
// the sampled activity trace.
#include "pe.hpp"
#include "kbuild/kernel_build_json.hpp"
#include "base/error.hpp"
#include "base/write_file.hpp"

#include "machine/memory_report.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <stdexcept>

namespace nesshi::machine {

nlohmann::json stage_cycles_json(const StageCycles& c) {
    return {{"processing", c.processing},
            {"communication", c.communication},
            {"wait", c.wait},
            {"bundles", c.bundles},
            {"ops", c.ops},
            {"processing_ops", c.processing_ops},
            {"units", c.units},
            {"ilp", c.ilp()},
            {"utilization", c.utilization()},
            {"words_received", c.words_received},
            {"words_sent", c.words_sent},
            {"modelled", c.modelled}};
}

StageCycles stage_cycles_from_json(const nlohmann::json& stage, const std::string& where) {
    auto count = [&](const char* key) {
        if (!stage.is_object() || !stage.contains(key)) throw std::runtime_error(fmt::format("missing \"{}{}\"", where, key));
        const nlohmann::json& v = stage.at(key);
        if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
            throw std::runtime_error(fmt::format("\"{}{}\" is not a count", where, key));
        return v.get<std::uint64_t>();
    };
    StageCycles c;
    c.processing = count("processing");
    c.communication = count("communication");
    c.wait = count("wait");
    c.bundles = count("bundles");
    c.ops = count("ops");
    c.processing_ops = count("processing_ops");
    c.units = count("units");
    c.words_received = count("words_received");
    c.words_sent = count("words_sent");
    if (!stage.contains("modelled") || !stage.at("modelled").is_boolean())
        throw std::runtime_error(fmt::format("\"{}modelled\" is missing or not true or false", where));
    c.modelled = stage.at("modelled").get<bool>();
    return c;
}

namespace {
double millions(std::uint64_t c) { return static_cast<double>(c) / 1e6; }
} // namespace

nlohmann::json stats_json(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo, const Result& r) {
    nlohmann::json j =
        with_memory_report(rt::stats_json(prep, opt, r.render, model_name(mo.model)), prep.grid, prep.shapes.shapes.size(), mo);
    // The kernels count no voxel steps or intersection tests, so of the native tracer's traversal
    // counters only `rays` (counted by SC) is known; the others are left out rather than given as 0.
    for (auto& [kind, counters] : j["traversal"].items()) counters = {{"rays", counters["rays"]}};
    const Stats& m = r.machine;
    nlohmann::json cycles = {{"total", m.total_cycles},
                             {"os", stage_cycles_json(m.os)},
                             {"ic", stage_cycles_json(m.ic)},
                             {"sc", stage_cycles_json(m.sc)},
                             {"pe", m.pe_cycles}};
    if (m.s_cycles) cycles["s_cycles"] = m.s_cycles; // model M, when exact (render.cpp)
    j["cycles"] = cycles;
    j["machine"] = {{"pes", mo.pes},
                    {"balance", mo.dynamic_balance ? nlohmann::json{{"mode", "dynamic"}, {"epoch", mo.epoch}}
                                                   : nlohmann::json{{"mode", "interleaved"}}},
                    {"window", mo.window},
                    {"fifo_capacity", mo.fifo_capacity},
                    {"fifo_latency", mo.fifo_latency},
                    {"quantum", mo.effective_quantum()},
                    {"cache", mo.cache.enabled ? nlohmann::json{{"enabled", true},
                                                                {"bytes", mo.cache.bytes},
                                                                {"line", mo.cache.line},
                                                                {"ways", mo.cache.ways},
                                                                {"miss_cycles", mo.cache.miss_cycles},
                                                                {"accesses", m.cache_accesses},
                                                                {"misses", m.cache_misses}}
                                               : nlohmann::json{{"enabled", false}}}, // ideal: every access hits
                    {"messages", {{"visit", m.visits}, {"return", m.returns}, {"miss", m.misses}, {"hit", m.hits}}},
                    {"max_fifo_words", m.max_fifo_words},
                    {"sc", "modelled: counted operations x seq latencies (machine/src/sc_cost.hpp)"}};
    if (mo.ray_slots) j["machine"]["ray_slots"] = mo.ray_slots; // limited rays in flight (0: all 4096)
    // Kernels scheduled for a machine other than their preset (absent when both are the committed ones).
    if (m.os_kernel.scheduled || m.ic_kernel.scheduled || !m.os_kernel.choice.empty() || !m.ic_kernel.choice.empty()) {
        auto build = [](const kbuild::KernelBuild& b) {
            nlohmann::json j{{"source", b.source}, {"machine", b.machine}, {"scheduled", b.scheduled},
                             {"blocks", b.blocks}, {"blocks_shortest", b.blocks_shortest}, {"nops_inserted", b.nops}};
            if (!b.choice.empty()) j["choice"] = b.choice;
            if (!b.loops.empty()) {
                j["loops"] = nlohmann::json::array();
                for (const kbuild::KernelLoop& l : b.loops) j["loops"].push_back(kbuild::loop_json(l));
            }
            return j;
        };
        j["machine"]["kernels"] = {{"os", build(m.os_kernel)}, {"ic", build(m.ic_kernel)}};
    }
    // What `nesshi sim` gives for one processor, for the OS and IC stages (SC is a cost model):
    // summed over PEs, and per PE when there are several.
    nlohmann::json detail = {{"os", iss::stats_json(m.os_detail)}, {"ic", iss::stats_json(m.ic_detail)}};
    if (m.per_pe.size() > 1) {
        detail["per_pe"] = nlohmann::json::array();
        for (const PeCycles& p : m.per_pe)
            detail["per_pe"].push_back({{"os", iss::stats_json(p.os_detail)}, {"ic", iss::stats_json(p.ic_detail)}});
    }
    j["detail"] = std::move(detail);
    j["host"]["wall_seconds"] = m.wall_seconds;
    j["host"]["machine_setup_seconds"] = m.machine_setup_seconds;
    j["host"]["simulated_bundles"] = m.simulated_bundles;
    j["host"]["bundles_per_second"] = m.bundles_per_second();
    j["host"]["threads"] = m.threads;
    return j;
}

std::string format_stats(const Stats& m) {
    std::string o;
    o += fmt::format("model {}: {:.3f} M cycles{}\n", model_name(m.model), millions(m.total_cycles),
                     m.pe_cycles.size() > 1 ? fmt::format(" (slowest of {} PEs)", m.pe_cycles.size()) : "");
    o += "stage   processing  communication        wait   (M cycles)    load   ILP  util  bundles\n";
    auto row = [&](const char* name, const StageCycles& c) {
        o += fmt::format("  {:<3} {:>12.3f} {:>14.3f} {:>11.3f}  {:>17.3f} {:>5.2f} {:>5.2f}  {}\n", name,
                         millions(c.processing), millions(c.communication), millions(c.wait), millions(c.load()),
                         c.ilp(), c.utilization(), c.modelled ? "modelled" : fmt::format("{}", c.bundles));
    };
    row("OS", m.os);
    row("IC", m.ic);
    row("SC", m.sc);
    const std::uint64_t lo = std::max<std::uint64_t>(1, std::min({m.os.load(), m.ic.load(), m.sc.load()}));
    auto ratio = [&](const StageCycles& c) { return static_cast<double>(c.load()) / static_cast<double>(lo); };
    o += fmt::format("load ratio OS:IC:SC = {:.0f}:{:.0f}:{:.0f}", ratio(m.os), ratio(m.ic), ratio(m.sc));
    if (m.s_cycles) o += fmt::format("   model S time of the same streams: {:.3f} M cycles", millions(m.s_cycles));
    o += "\n";
    o += fmt::format("messages: {} VISIT, {} RETURN, {} HIT, {} MISS; largest FIFO {} words", m.visits, m.returns,
                     m.hits, m.misses, m.max_fifo_words);
    if (m.cache_accesses)
        o += fmt::format("; IC cache {:.2f}% misses of {}", 100.0 * static_cast<double>(m.cache_misses) /
                                                               static_cast<double>(m.cache_accesses),
                         m.cache_accesses);
    o += "\n";
    for (const auto& [stage, b] : {std::pair{"OS", &m.os_kernel}, std::pair{"IC", &m.ic_kernel}}) {
        if (b->scheduled) {
            std::string loops;
            for (const kbuild::KernelLoop& l : b->loops)
                loops += fmt::format("; {} loop at line {}: II {} (MII {}), {} stage{}, unrolled {}x, one iteration {} cycles "
                                     "(longest path {})",
                                     l.is_while ? "while" : "counted", l.line, l.ii, l.mii, l.stages, l.stages == 1 ? "" : "s",
                                     l.unroll, l.iteration, l.longest_path);
            o += fmt::format("{} kernel: {} scheduled for {} ({} blocks, {} proven shortest; {} nop bundle{} in its hand-scheduled "
                             "code for the latencies{})\n",
                             stage, b->source, b->machine, b->blocks, b->blocks_shortest, b->nops, b->nops == 1 ? "" : "s", loops);
        }
        if (!b->choice.empty()) o += fmt::format("{} kernel for {}: {}\n", stage, b->machine, b->choice);
    }
    o += fmt::format("host: {:.2f} s, {:.1f} M bundles simulated, {:.1f} M bundles/s ({} thread{})\n", m.wall_seconds,
                     millions(m.simulated_bundles), m.bundles_per_second() / 1e6, m.threads, m.threads == 1 ? "" : "s");
    return o;
}

// Chrome trace events (the format Perfetto reads): per PE a process, per stage a thread with "X"
// slices; 1 trace microsecond = 1 machine cycle. Within an Activity stretch the order of its
// kinds is not known (a stretch spans one scheduler step or more); it is drawn wait, then
// communication, then processing, with neighbouring slices of one kind joined.
void write_trace_json(const std::string& path, const std::vector<PeResult>& pes) {
    nlohmann::json events = nlohmann::json::array();
    static constexpr const char* kFifo[4] = {"FIFO OS in (DIS, SC, IC)", "FIFO IC in (OS)", "FIFO SC in (OS)",
                                             "FIFO SC in (IC)"};
    static constexpr const char* kStage[3] = {"OS", "IC", "SC (modelled)"};
    static constexpr const char* kKind[3] = {"wait", "communication", "processing"};
    struct Slice {
        std::uint64_t start, end;
        int kind;
    };
    for (std::size_t p = 0; p < pes.size(); ++p) {
        events.push_back({{"name", "process_name"}, {"ph", "M"}, {"pid", p}, {"args", {{"name", fmt::format("PE {}", p)}}}});
        events.push_back({{"name", "process_sort_index"}, {"ph", "M"}, {"pid", p}, {"args", {{"sort_index", p}}}});
        std::array<std::vector<Slice>, 3> slices;
        for (int k = 0; k < 3; ++k) {
            events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", p}, {"tid", k}, {"args", {{"name", kStage[k]}}}});
            events.push_back({{"name", "thread_sort_index"}, {"ph", "M"}, {"pid", p}, {"tid", k}, {"args", {{"sort_index", k}}}});
            for (const Activity& a : pes[p].activity[k]) {
                std::uint64_t t = a.start;
                const std::uint64_t len[3] = {a.wait, a.communication, a.processing};
                for (int kind = 0; kind < 3; ++kind) {
                    if (!len[kind]) continue;
                    auto& v = slices[k];
                    if (!v.empty() && v.back().kind == kind && v.back().end == t) v.back().end = t + len[kind];
                    else v.push_back({t, t + len[kind], kind});
                    t += len[kind];
                }
            }
            for (const Slice& sl : slices[k])
                events.push_back({{"name", kKind[sl.kind]}, {"cat", "stage"}, {"ph", "X"}, {"pid", p}, {"tid", k},
                                  {"ts", sl.start}, {"dur", sl.end - sl.start}});
        }
        // Counters: FIFO words at each sample, and each stage's busy fraction (processing +
        // communication slices) over the interval to the next sample.
        const auto& s = pes[p].samples;
        std::array<std::size_t, 3> next{}; // per stage: the first slice not wholly before the interval
        for (std::size_t i = 0; i < s.size(); ++i) {
            for (int f = 0; f < 4; ++f)
                events.push_back({{"name", kFifo[f]}, {"ph", "C"}, {"pid", p}, {"ts", s[i].cycle},
                                  {"args", {{"words", s[i].fifo[f]}}}});
            if (i + 1 == s.size() || s[i + 1].cycle <= s[i].cycle) continue;
            const std::uint64_t lo = s[i].cycle, hi = s[i + 1].cycle;
            nlohmann::json args;
            for (int k = 0; k < 3; ++k) {
                const auto& v = slices[k];
                while (next[k] < v.size() && v[next[k]].end <= lo) ++next[k];
                std::uint64_t busy = 0;
                for (std::size_t j = next[k]; j < v.size() && v[j].start < hi; ++j)
                    if (v[j].kind != 0) busy += std::min(hi, v[j].end) - std::max(lo, v[j].start);
                args[k == 2 ? "SC" : kStage[k]] = static_cast<double>(busy) / static_cast<double>(hi - lo);
            }
            events.push_back({{"name", "activity (busy fraction)"}, {"ph", "C"}, {"pid", p}, {"ts", lo}, {"args", args}});
        }
    }
    nlohmann::json doc = {{"traceEvents", events},
                          {"displayTimeUnit", "ns"},
                          {"otherData", {{"time_unit", "1 trace microsecond = 1 machine cycle"}}}};
    base::write_file(path, doc.dump() + "\n");
}

} // namespace nesshi::machine
