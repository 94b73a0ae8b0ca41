// The loop report for hand-written loops (see loop_report.hpp).
#include "sched/loop_report.hpp"

#include "circuits.hpp"

#include "sched/bounds.hpp"

#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/printer.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace nesshi::sched {

namespace {

struct LoopOp {
    isa::Instr in;
    int bundle = 0; // issue cycle within the body
    int latency = 1;
};

std::string reg_name(isa::RegFile f, int r) { return fmt::format("{}{}", f == isa::RegFile::Int ? 'r' : 'f', r); }

// True register dependences of the body run as a loop with period ii: a read sees the write that
// landed last by its cycle, from this iteration or an earlier one (its distance).
std::vector<DepEdge> true_dependences(const std::vector<LoopOp>& ops, int ii) {
    std::vector<DepEdge> edges;
    for (std::size_t u = 0; u < ops.size(); ++u)
        for (const isa::RegOperand& r : isa::register_operands(ops[u].in)) {
            if (r.write) continue;
            int best = -1, best_dist = 0;
            std::int64_t best_land = 0;
            for (std::size_t w = 0; w < ops.size(); ++w)
                for (const isa::RegOperand& o : isa::register_operands(ops[w].in)) {
                    if (!o.write || o.file != r.file || o.reg != r.reg) continue;
                    const std::int64_t land0 = ops[w].bundle + ops[w].latency;
                    // the latest iteration d >= 0 back whose write has landed when u reads
                    int d = 0;
                    while (land0 - static_cast<std::int64_t>(d) * ii > ops[u].bundle) ++d;
                    const std::int64_t land = land0 - static_cast<std::int64_t>(d) * ii;
                    if (best < 0 || land > best_land) best = static_cast<int>(w), best_dist = d, best_land = land;
                }
            if (best >= 0) edges.push_back({best, static_cast<int>(u), ops[static_cast<std::size_t>(best)].latency, best_dist});
        }
    return edges;
}

} // namespace

std::vector<LoopReport> analyse_loops(const isa::ObjectFile& obj, const isa::Machine& m, const std::string& label) {
    const std::vector<std::vector<isa::Instr>> bundles = isa::decode_bundles(obj);
    std::vector<LoopReport> out;
    for (const isa::Symbol& sym : obj.symbols) {
        if (sym.kind != isa::SymbolKind::Code || (!label.empty() && sym.name != label)) continue;
        // From the label to the first branch back to it; conditional exits on the way are allowed
        // (a loop with data-dependent exits), any other jump or a halt ends the search.
        std::uint32_t end = sym.value;
        bool loop = false, stop = false;
        for (; end < bundles.size() && !loop && !stop; ++end)
            for (const isa::Instr& in : bundles[end]) {
                const isa::Kind k = in.info().kind;
                if ((k == isa::Kind::Branch || k == isa::Kind::Jump) && in.imm == sym.value) loop = true;
                else if (k == isa::Kind::Jump || k == isa::Kind::JumpLink || k == isa::Kind::JumpReg || k == isa::Kind::Halt)
                    stop = true;
            }
        --end;
        if (!loop) continue;
        LoopReport r;
        r.label = sym.name;
        r.first = sym.value;
        r.last = end;
        if (sym.value < obj.lines.size() && obj.lines[sym.value].file < obj.files.size())
            r.source = fmt::format("{}:{}", obj.files[obj.lines[sym.value].file], obj.lines[sym.value].line);
        r.bundles = static_cast<int>(end - sym.value + 1);
        r.ii = r.bundles + static_cast<int>(m.branch_penalty);
        std::vector<LoopOp> ops;
        for (std::uint32_t b = r.first; b <= r.last; ++b)
            for (const isa::Instr& in : bundles[b])
                if (in.info().kind != isa::Kind::Nop)
                    ops.push_back({in, static_cast<int>(b - r.first), static_cast<int>(m.latency_of(in.info()))});
        r.ops = static_cast<int>(ops.size());
        std::vector<isa::Instr> instrs;
        for (const LoopOp& o : ops) instrs.push_back(o.in);
        const ResBound res = res_mii(m, instrs); // the loop's own control ops are among them
        r.res_mii = res.ii();
        r.res_binding = res.binds;
        const std::vector<DepEdge> deps = true_dependences(ops, r.ii);
        r.rec_mii = recurrence_mii(static_cast<int>(ops.size()), deps);
        if (r.rec_mii > 1)
            for (int k : positive_circuit(static_cast<int>(ops.size()), deps, r.rec_mii - 1)) {
                const DepEdge& e = deps[static_cast<std::size_t>(k)];
                r.critical.push_back(isa::format_instr(ops[static_cast<std::size_t>(e.from)].in));
                r.critical_latency += e.latency;
                r.critical_distance += e.distance;
            }
        // Resources per iteration against their capacity at the achieved II.
        for (std::size_t s = 0; s < m.slots.size(); ++s) {
            ResourceUse u{m.slots[s].name, 0, static_cast<std::uint32_t>(r.ii)};
            for (const LoopOp& o : ops) u.used += o.in.slot == s;
            r.resources.push_back(u);
        }
        for (int f = 0; f < 2; ++f) {
            ResourceUse rd{fmt::format("{} reads", isa::kRegFileNames[static_cast<std::size_t>(f)]), 0,
                           static_cast<std::uint32_t>(r.ii) * m.regs[static_cast<std::size_t>(f)].read_ports};
            ResourceUse wr{fmt::format("{} writes", isa::kRegFileNames[static_cast<std::size_t>(f)]), 0,
                           static_cast<std::uint32_t>(r.ii) * m.regs[static_cast<std::size_t>(f)].write_ports};
            for (const LoopOp& o : ops)
                for (const isa::RegOperand& x : isa::register_operands(o.in))
                    if (static_cast<int>(x.file) == f) ++(x.write ? wr.used : rd.used);
            r.resources.push_back(rd);
            r.resources.push_back(wr);
            r.file_size[f] = m.regs[static_cast<std::size_t>(f)].count;
        }
        // Lifetimes: each register written in the body, from the write's issue to its last read.
        std::map<std::pair<int, int>, int> life;
        std::map<std::pair<int, int>, int> born;
        for (const DepEdge& e : deps) {
            const LoopOp& w = ops[static_cast<std::size_t>(e.from)];
            for (const isa::RegOperand& o : isa::register_operands(w.in)) {
                if (!o.write) continue;
                const auto key = std::make_pair(static_cast<int>(o.file), static_cast<int>(o.reg));
                const int end_cycle = ops[static_cast<std::size_t>(e.to)].bundle + e.distance * r.ii;
                life[key] = std::max(life[key], end_cycle - w.bundle);
                born[key] = w.bundle;
            }
        }
        std::vector<int> live[2];
        live[0].assign(static_cast<std::size_t>(r.ii), 0);
        live[1].assign(static_cast<std::size_t>(r.ii), 0);
        for (const auto& [key, cycles] : life) {
            r.lifetimes.push_back({reg_name(static_cast<isa::RegFile>(key.first), key.second), cycles});
            for (int c = 0; c < std::max(1, cycles); ++c) ++live[key.first][static_cast<std::size_t>((born[key] + c) % r.ii)];
        }
        for (int f = 0; f < 2; ++f) r.max_live[f] = *std::max_element(live[f].begin(), live[f].end());
        for (std::uint32_t b = r.first; b <= r.last; ++b) {
            std::vector<isa::Instr> in = bundles[b];
            const isa::BundleUsage u = isa::bundle_usage(in);
            std::string cells;
            for (const isa::Instr& x : in)
                if (x.info().kind != isa::Kind::Nop) cells += fmt::format(" {}:{}", m.slots[x.slot].name, x.info().mnemonic);
            r.mrt.push_back(fmt::format("{:>3} |{:<44} IRF r{}/w{}  FPRF r{}/w{}", b - r.first, cells, u.reads[0], u.writes[0],
                                        u.reads[1], u.writes[1]));
        }
        const int bound = std::max(r.res_mii, r.rec_mii);
        if (r.ii == bound) r.verdict = "at the bound";
        else
            r.verdict = fmt::format("{} cycle{} above the bound {} ({}{})", r.ii - bound, r.ii - bound == 1 ? "" : "s", bound,
                                    r.res_mii >= r.rec_mii ? "resources: " + r.res_binding : "recurrence",
                                    m.branch_penalty ? fmt::format("; the taken branch costs {} bubble cycle{}", m.branch_penalty,
                                                                   m.branch_penalty == 1 ? "" : "s")
                                                     : "");
        out.push_back(std::move(r));
    }
    if (!label.empty() && out.empty()) throw std::runtime_error(fmt::format("'{}' is not a loop (a label whose block ends in a branch back to it)", label));
    return out;
}

std::string LoopReport::text() const {
    std::string o = fmt::format("# LOOP {} ({}, bundles {}-{})\n", label, source, first, last);
    o += fmt::format("#   bundles {}, achieved II {}, {} operations ({:.2f} per cycle)\n", bundles, ii, ops,
                     static_cast<double>(ops) / ii);
    o += fmt::format("#   resource bound (ResMII)    {}  ({})\n", res_mii, res_binding);
    if (critical.empty()) o += fmt::format("#   recurrence bound (RecMII)  {}  (no register recurrence longer than a cycle)\n", rec_mii);
    else {
        std::string chain;
        for (const std::string& c : critical) chain += (chain.empty() ? "" : " -> ") + c;
        o += fmt::format("#   recurrence bound (RecMII)  {}  ({}: {} cycles, distance {})\n", rec_mii, chain,
                         critical_latency, critical_distance);
    }
    o += fmt::format("#   verdict: {}\n", verdict);
    o += "#   resources per iteration (used / capacity at this II)\n";
    for (const ResourceUse& u : resources) o += fmt::format("#     {:<12} {:>4} / {:<4}\n", u.name, u.used, u.capacity);
    o += fmt::format("#   MaxLive: IRF {} of {}, FPRF {} of {}\n", max_live[0], file_size[0], max_live[1], file_size[1]);
    for (const Lifetime& l : lifetimes) o += fmt::format("#     {:<5} lives {} cycle{}\n", l.reg, l.cycles, l.cycles == 1 ? "" : "s");
    o += "#   reservation table (cycle: slot:op ... and register ports read/written)\n";
    for (const std::string& row : mrt) o += "#   " + row + "\n";
    return o;
}

std::string LoopReport::json() const {
    nlohmann::json j{{"label", label}, {"source", source}, {"first_bundle", first}, {"last_bundle", last},
                     {"bundles", bundles}, {"ii", ii}, {"ops", ops}, {"res_mii", res_mii}, {"res_binding", res_binding},
                     {"rec_mii", rec_mii}, {"critical_circuit", critical}, {"critical_latency", critical_latency},
                     {"critical_distance", critical_distance}, {"verdict", verdict},
                     {"max_live", {{"irf", max_live[0]}, {"fprf", max_live[1]}}}};
    for (const ResourceUse& u : resources) j["resources"].push_back({{"name", u.name}, {"used", u.used}, {"capacity", u.capacity}});
    for (const Lifetime& l : lifetimes) j["lifetimes"].push_back({{"register", l.reg}, {"cycles", l.cycles}});
    j["reservation_table"] = mrt;
    return j.dump(2);
}

} // namespace nesshi::sched
