// Statistics views: derived from per-bundle counters (see stats.hpp for every field).
#include "iss/stats.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>

namespace nesshi::iss {

namespace {
double ratio(uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; }

void trim_hist(std::vector<uint64_t>& h) {
    while (h.size() > 1 && h.back() == 0) h.pop_back();
}

// The ratios of the counts: ILP, utilisation of the whole, of each unit and of each port file.
void derive_ratios(Stats& s) {
    s.ilp = ratio(s.processing_ops, s.processing_cycles);
    s.ops_per_bundle = ratio(s.ops, s.bundles);
    s.utilisation = s.slots ? s.ilp / s.slots : 0;
    for (auto& u : s.units) u.utilisation = ratio(u.ops, s.processing_cycles);
    for (auto& ps : s.ports) {
        ps.read_utilisation = ratio(ps.reads, uint64_t{ps.read_ports} * s.cycles);
        ps.write_utilisation = ratio(ps.writes, uint64_t{ps.write_ports} * s.cycles);
    }
    for (auto& r : s.regions) r.ilp = ratio(r.processing_ops, r.processing_cycles);
}

void add_hist(std::vector<uint64_t>& into, const std::vector<uint64_t>& add) {
    if (into.size() < add.size()) into.resize(add.size(), 0);
    for (size_t i = 0; i < add.size(); ++i) into[i] += add[i];
}
} // namespace

Stats compute_stats(const Processor& p, size_t hot) {
    const Program& prog = p.program();
    const isa::Machine& m = prog.machine();
    const Counters& k = p.counters();
    Stats s;
    s.machine = m.name;
    s.slots = uint32_t(m.slots.size());
    for (const auto& sl : m.slots) s.units.push_back({sl.name, 0, 0, 0});
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        PortStats ps;
        ps.file = std::string(isa::kRegFileNames[f]);
        ps.read_ports = m.regs[f].read_ports;
        ps.write_ports = m.regs[f].write_ports;
        ps.read_hist.assign(isa::kMaxSlots * 3 + 1, 0);
        ps.write_hist = p.write_histogram(f);
        s.ports.push_back(std::move(ps));
    }
    const uint32_t penalty = m.branch_penalty;
    s.ilp_hist.assign(isa::kMaxSlots + 1, 0);
    for (uint32_t pc = 0; pc < prog.size(); ++pc) {
        const DecodedBundle& b = prog.bundles()[pc];
        uint64_t n = k.exec[pc];
        s.bundles += n;
        s.ilp_hist[std::min<size_t>(b.ops, isa::kMaxSlots)] += n;
        s.ops += n * b.ops;
        if (b.fifo) {
            s.communication_cycles += n;
        } else {
            s.processing_bundles += n;
            s.processing_ops += n * b.ops;
        }
        for (uint32_t sl = 0; sl < s.slots; ++sl)
            if (b.slot_mask >> sl & 1u) (b.fifo ? s.units[sl].comm_ops : s.units[sl].ops) += n;
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            s.ports[f].reads += n * b.reads[f];
            s.ports[f].read_hist[std::min<size_t>(b.reads[f], s.ports[f].read_hist.size() - 1)] += n;
        }
        s.taken_branches += k.taken[pc];
    }
    s.bubble_cycles = k.bubble_cycles;
    s.stall_cycles = k.stall_cycles;
    s.wait_cycles = k.wait_cycles;
    s.processing_cycles = s.processing_bundles + s.bubble_cycles + s.stall_cycles;
    s.cycles = s.processing_cycles + s.communication_cycles + s.wait_cycles;
    s.words_received = k.words_received;
    s.words_sent = k.words_sent;
    for (auto& ps : s.ports) {
        ps.read_hist[0] += s.cycles - s.bundles;
        for (size_t n = 0; n < ps.write_hist.size(); ++n) ps.writes += n * ps.write_hist[n];
        trim_hist(ps.read_hist);
        trim_hist(ps.write_hist);
    }
    trim_hist(s.ilp_hist);
    derive_ratios(s);
    for (const Region& r : prog.regions()) {
        RegionStats rs{r.label, r.first, r.end};
        for (uint32_t pc = r.first; pc < r.end; ++pc) {
            const DecodedBundle& b = prog.bundles()[pc];
            uint64_t n = k.exec[pc];
            rs.bundles += n;
            rs.ops += n * b.ops;
            (b.fifo ? rs.communication_cycles : rs.processing_cycles) += n;
            rs.processing_cycles += k.taken[pc] * penalty + k.stall[pc];
            rs.wait_cycles += k.wait[pc];
        }
        for (uint32_t pc = r.first; pc < r.end; ++pc)
            if (!prog.bundles()[pc].fifo) rs.processing_ops += k.exec[pc] * prog.bundles()[pc].ops;
        rs.cycles = rs.processing_cycles + rs.communication_cycles + rs.wait_cycles;
        rs.ilp = ratio(rs.processing_ops, rs.processing_cycles);
        s.regions.push_back(std::move(rs));
    }
    std::vector<uint32_t> order(prog.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return k.exec[a] > k.exec[b]; });
    for (uint32_t pc : order) {
        if (s.hot.size() >= hot || k.exec[pc] == 0) break;
        s.hot.push_back({pc, prog.code_name(pc), prog.source_of(pc), prog.format_bundle(pc), k.exec[pc],
                         prog.bundles()[pc].ops});
    }
    return s;
}

void accumulate(Stats& into, const Stats& add) {
    if (into.machine.empty()) {
        into = add;
        into.hot.clear();
        return;
    }
    into.cycles += add.cycles;
    into.processing_cycles += add.processing_cycles;
    into.communication_cycles += add.communication_cycles;
    into.wait_cycles += add.wait_cycles;
    into.bubble_cycles += add.bubble_cycles;
    into.stall_cycles += add.stall_cycles;
    into.bundles += add.bundles;
    into.processing_bundles += add.processing_bundles;
    into.ops += add.ops;
    into.processing_ops += add.processing_ops;
    into.taken_branches += add.taken_branches;
    into.words_received += add.words_received;
    into.words_sent += add.words_sent;
    add_hist(into.ilp_hist, add.ilp_hist);
    for (size_t i = 0; i < into.units.size() && i < add.units.size(); ++i) {
        into.units[i].ops += add.units[i].ops;
        into.units[i].comm_ops += add.units[i].comm_ops;
    }
    for (size_t i = 0; i < into.ports.size() && i < add.ports.size(); ++i) {
        into.ports[i].reads += add.ports[i].reads;
        into.ports[i].writes += add.ports[i].writes;
        add_hist(into.ports[i].read_hist, add.ports[i].read_hist);
        add_hist(into.ports[i].write_hist, add.ports[i].write_hist);
    }
    for (size_t i = 0; i < into.regions.size() && i < add.regions.size(); ++i) {
        RegionStats& r = into.regions[i];
        const RegionStats& a = add.regions[i];
        r.cycles += a.cycles;
        r.processing_cycles += a.processing_cycles;
        r.communication_cycles += a.communication_cycles;
        r.wait_cycles += a.wait_cycles;
        r.bundles += a.bundles;
        r.ops += a.ops;
        r.processing_ops += a.processing_ops;
    }
    derive_ratios(into);
}

std::string stats_text(const Stats& s) {
    std::string o;
    o += fmt::format("machine {} ({} slots)\n", s.machine, s.slots);
    o += fmt::format("cycles          {:>12}  = processing {} + communication {} + wait {}\n", s.cycles,
                     s.processing_cycles, s.communication_cycles, s.wait_cycles);
    o += fmt::format("  processing    {:>12}  = bundles {} + branch bubbles {} + memory stalls {}\n",
                     s.processing_cycles, s.processing_bundles, s.bubble_cycles, s.stall_cycles);
    o += fmt::format("bundles issued  {:>12}\n", s.bundles);
    o += fmt::format("operations      {:>12}  ({:.2f} per bundle; nops not counted)\n", s.ops, s.ops_per_bundle);
    o += fmt::format("ILP             {:>12.2f}  operations per bundle over processing cycles\n", s.ilp);
    o += fmt::format("utilisation     {:>12.2f}  ILP / {} slots\n", s.utilisation, s.slots);
    o += fmt::format("taken branches  {:>12}\n", s.taken_branches);
    {
        std::string h;
        for (size_t i = 0; i < s.ilp_hist.size(); ++i) h += fmt::format("{}{}", i ? " " : "", s.ilp_hist[i]);
        o += fmt::format("bundles by ops  {:>12}  (bundles issued with 0, 1, 2, ... operations)\n", h);
    }
    o += fmt::format("FIFO words      {:>12}  received, {} sent\n", s.words_received, s.words_sent);
    o += "\nunit        ops   comm ops  utilisation\n";
    for (const auto& u : s.units)
        o += fmt::format("{:<6} {:>10} {:>10} {:>12.2f}\n", u.name, u.ops, u.comm_ops, u.utilisation);
    o += "\nfile  ports  used(r/w)           utilisation(r/w)  cycles using 0,1,2,... ports\n";
    for (const auto& p : s.ports) {
        auto hist = [](const std::vector<uint64_t>& h) {
            std::string t;
            for (size_t i = 0; i < h.size(); ++i) t += fmt::format("{}{}", i ? " " : "", h[i]);
            return t;
        };
        o += fmt::format("{:<5} {}r/{}w  {:>9}/{:<9}  {:>6.2f}/{:<6.2f}        r: {}\n", p.file, p.read_ports,
                         p.write_ports, p.reads, p.writes, p.read_utilisation, p.write_utilisation, hist(p.read_hist));
        o += fmt::format("{:<56}w: {}\n", "", hist(p.write_hist));
    }
    if (!s.regions.empty()) {
        o += "\nregion                 bundles      cycles  processing   comm    wait        ops    ILP\n";
        for (const auto& r : s.regions)
            o += fmt::format("{:<18} {:>11} {:>11} {:>11} {:>6} {:>7} {:>10} {:>6.2f}\n", r.label, r.bundles, r.cycles,
                             r.processing_cycles, r.communication_cycles, r.wait_cycles, r.ops, r.ilp);
    }
    if (!s.hot.empty()) {
        o += "\nhot bundles (executions)\n";
        for (const auto& h : s.hot)
            o += fmt::format("{:>12}  {:>5} {:<16} {:<16} {}\n", h.exec, h.pc, h.name, h.source, h.text);
    }
    return o;
}

nlohmann::json stats_json(const Stats& s) {
    using nlohmann::json;
    json j;
    j["machine"] = s.machine;
    j["slots"] = s.slots;
    j["cycles"] = s.cycles;
    j["processing_cycles"] = s.processing_cycles;
    j["communication_cycles"] = s.communication_cycles;
    j["wait_cycles"] = s.wait_cycles;
    j["bubble_cycles"] = s.bubble_cycles;
    j["stall_cycles"] = s.stall_cycles;
    j["bundles"] = s.bundles;
    j["processing_bundles"] = s.processing_bundles;
    j["ops"] = s.ops;
    j["processing_ops"] = s.processing_ops;
    j["ilp"] = s.ilp;
    j["ops_per_bundle"] = s.ops_per_bundle;
    j["utilization"] = s.utilisation;
    j["ilp_hist"] = s.ilp_hist;
    j["taken_branches"] = s.taken_branches;
    j["words_received"] = s.words_received;
    j["words_sent"] = s.words_sent;
    j["units"] = json::array();
    for (const auto& u : s.units)
        j["units"].push_back({{"name", u.name}, {"ops", u.ops}, {"comm_ops", u.comm_ops}, {"utilization", u.utilisation}});
    j["ports"] = json::array();
    for (const auto& p : s.ports)
        j["ports"].push_back({{"file", p.file}, {"read_ports", p.read_ports}, {"write_ports", p.write_ports},
                              {"reads", p.reads}, {"writes", p.writes}, {"read_utilization", p.read_utilisation},
                              {"write_utilization", p.write_utilisation}, {"read_hist", p.read_hist},
                              {"write_hist", p.write_hist}});
    j["regions"] = json::array();
    for (const auto& r : s.regions)
        j["regions"].push_back({{"label", r.label}, {"first", r.first}, {"end", r.end}, {"cycles", r.cycles},
                                {"processing_cycles", r.processing_cycles},
                                {"communication_cycles", r.communication_cycles}, {"wait_cycles", r.wait_cycles},
                                {"bundles", r.bundles}, {"ops", r.ops}, {"ilp", r.ilp}});
    j["hot"] = json::array();
    for (const auto& h : s.hot)
        j["hot"].push_back({{"pc", h.pc}, {"name", h.name}, {"source", h.source}, {"exec", h.exec}, {"ops", h.ops},
                            {"text", h.text}});
    return j;
}

} // namespace nesshi::iss
