// The loop report for hand-written loops (see loop_report.hpp).
#include "sched/loop_report.hpp"

#include "sched/bounds.hpp"
#include "sched/ddg.hpp"

#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/printer.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

namespace nesshi::sched {

namespace {

std::string reg_name(isa::RegFile f, int r) { return fmt::format("{}{}", f == isa::RegFile::Int ? 'r' : 'f', r); }

// The report of one pass over `path` (bundle indices in the order they issue) as a loop body.
LoopReport analyse_region(const std::vector<std::vector<isa::Instr>>& bundles, const isa::ObjectFile& obj,
                          const isa::Machine& m, const std::string& label, const std::vector<std::uint32_t>& path) {
    LoopReport r;
    r.label = label;
    r.machine = m.name;
    for (const isa::SlotDesc& s : m.slots) r.slots.push_back(s.name);
    r.first = path.front();
    r.last = path.back();
    if (r.first < obj.lines.size() && obj.lines[r.first].file < obj.files.size())
    r.source = fmt::format("{}:{}", obj.files[obj.lines[r.first].file], obj.lines[r.first].line);
    r.bundles = static_cast<int>(path.size());
    r.ii = r.bundles + static_cast<int>(m.branch_penalty);
    std::vector<BodyOp> ops;
    for (std::size_t c = 0; c < path.size(); ++c)
        for (const isa::Instr& in : bundles[path[c]])
            if (in.info().kind != isa::Kind::Nop) ops.push_back({in, static_cast<std::uint32_t>(c)});
    r.ops = static_cast<int>(ops.size());
    std::vector<isa::Instr> instrs;
    for (const BodyOp& o : ops) instrs.push_back(o.instr);
    const ResBound res = res_mii(m, instrs); // the loop's own control ops are among them
    r.res_mii = res.ii();
    r.res_binding = res.binds;
    const Ddg deps = scheduled_loop_ddg(m, ops, r.ii);
    r.rec_mii = deps.rec_mii();
    for (int k : deps.critical()) {
        const Dep& e = deps.edges[static_cast<std::size_t>(k)];
        r.critical.push_back(isa::format_instr(ops[static_cast<std::size_t>(e.from)].instr));
        r.critical_latency += e.latency;
        r.critical_distance += e.distance;
    }
    // Resources per iteration against their capacity at the achieved II.
    for (std::size_t s = 0; s < m.slots.size(); ++s) {
        ResourceUse u{m.slots[s].name, 0, static_cast<std::uint32_t>(r.ii)};
        for (const BodyOp& o : ops) u.used += o.instr.slot == s;
        r.resources.push_back(u);
    }
    for (int f = 0; f < 2; ++f) {
        ResourceUse rd{fmt::format("{} reads", isa::kRegFileNames[static_cast<std::size_t>(f)]), 0,
                       static_cast<std::uint32_t>(r.ii) * m.regs[static_cast<std::size_t>(f)].read_ports};
        ResourceUse wr{fmt::format("{} writes", isa::kRegFileNames[static_cast<std::size_t>(f)]), 0,
                       static_cast<std::uint32_t>(r.ii) * m.regs[static_cast<std::size_t>(f)].write_ports};
        for (const BodyOp& o : ops)
            for (const isa::RegOperand& x : isa::register_operands(o.instr))
                if (static_cast<int>(x.file) == f) ++(x.write ? wr.used : rd.used);
        r.resources.push_back(rd);
        r.resources.push_back(wr);
        r.file_size[f] = m.regs[static_cast<std::size_t>(f)].count;
        r.read_ports[f] = m.regs[static_cast<std::size_t>(f)].read_ports;
        r.write_ports[f] = m.regs[static_cast<std::size_t>(f)].write_ports;
    }
    // Lifetimes: each register written in the body, from the write's issue to its last read.
    std::map<std::pair<int, int>, int> life;
    std::map<std::pair<int, int>, int> born;
    for (const Dep& e : deps.edges) {
        const BodyOp& w = ops[static_cast<std::size_t>(e.from)];
        const int issue = static_cast<int>(w.bundle);
        for (const isa::RegOperand& o : isa::register_operands(w.instr)) {
            if (!o.write) continue;
            const auto key = std::make_pair(static_cast<int>(o.file), static_cast<int>(o.reg));
            const int end_cycle = static_cast<int>(ops[static_cast<std::size_t>(e.to)].bundle) + e.distance * r.ii;
            life[key] = std::max(life[key], end_cycle - issue);
            born[key] = issue;
        }
    }
    std::vector<int> live[2];
    live[0].assign(static_cast<std::size_t>(r.ii), 0);
    live[1].assign(static_cast<std::size_t>(r.ii), 0);
    for (const auto& [key, cycles] : life) {
        r.lifetimes.push_back({reg_name(static_cast<isa::RegFile>(key.first), key.second), cycles, born[key], key.first});
        for (int c = 0; c < std::max(1, cycles); ++c) ++live[key.first][static_cast<std::size_t>((born[key] + c) % r.ii)];
    }
    for (int f = 0; f < 2; ++f) r.max_live[f] = *std::max_element(live[f].begin(), live[f].end());
    for (std::size_t c = 0; c < path.size(); ++c) {
        std::vector<isa::Instr> in = bundles[path[c]];
        const isa::BundleUsage u = isa::bundle_usage(in);
        std::string cells;
        TableRow row;
        for (const isa::Instr& x : in)
            if (x.info().kind != isa::Kind::Nop) {
                cells += fmt::format(" {}:{}", m.slots[x.slot].name, x.info().mnemonic);
                row.ops.push_back({m.slots[x.slot].name, std::string(x.info().mnemonic),
                                   std::string(isa::kOpClassNames[static_cast<std::size_t>(x.info().cls)])});
            }
        for (int f = 0; f < 2; ++f) {
            row.reads[f] = u.reads[static_cast<std::size_t>(f)];
            row.writes[f] = u.writes[static_cast<std::size_t>(f)];
        }
        r.table.push_back(row);
        r.mrt.push_back(fmt::format("{:>3} |{:<44} IRF r{}/w{}  FPRF r{}/w{}", c, cells, u.reads[0], u.writes[0],
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
    return r;
}

bool ends_flow(isa::Kind k) {
    return k == isa::Kind::Jump || k == isa::Kind::JumpLink || k == isa::Kind::JumpReg || k == isa::Kind::Halt;
}

// The code labels whose address the program stores (`li rX, label` then `sw rX, ...` before rX
// is written again: a dispatch table's entry), the targets a `jr` may reach.
std::vector<const isa::Symbol*> address_taken(const isa::ObjectFile& obj, const std::vector<std::vector<isa::Instr>>& bundles) {
    constexpr std::size_t kReach = 8; // bundles searched for the store after the li
    std::vector<std::uint32_t> stored;
    for (std::size_t b = 0; b < bundles.size(); ++b)
        for (const isa::Instr& li : bundles[b]) {
            if (li.info().mnemonic != "li") continue;
            bool found = false, overwritten = false;
            for (std::size_t c = b; c < std::min(bundles.size(), b + kReach) && !found && !overwritten; ++c)
                for (const isa::Instr& in : bundles[c]) {
                    if (in.info().kind == isa::Kind::Store && in.info().mnemonic == "sw" && in.rs2 == li.rd && c > b) found = true;
                    else if (c > b && !found)
                        for (const isa::RegOperand& o : isa::register_operands(in))
                            if (o.write && o.file == isa::RegFile::Int && o.reg == li.rd) overwritten = true;
                }
            if (found) stored.push_back(static_cast<std::uint32_t>(li.imm));
        }
    std::vector<const isa::Symbol*> out;
    for (const isa::Symbol& sym : obj.symbols)
        if (sym.kind == isa::SymbolKind::Code && std::find(stored.begin(), stored.end(), sym.value) != stored.end())
            out.push_back(&sym);
    return out;
}

// The pass of a dispatch loop that starts at `entry` (a jr target): its bundles in issue order,
// following unconditional jumps, falling through conditional branches (early exits: a test that
// fails leaves the pass), to the first `jr` (the dispatch to the next pass). Empty when the path
// halts, calls, loops back on itself or runs off the code before a `jr`.
std::vector<std::uint32_t> dispatch_pass(const std::vector<std::vector<isa::Instr>>& bundles, std::uint32_t entry) {
    std::vector<std::uint32_t> path;
    std::vector<bool> seen(bundles.size(), false);
    for (std::uint32_t b = entry; b < bundles.size();) {
        if (seen[b]) return {};
        seen[b] = true;
        path.push_back(b);
        std::optional<std::uint32_t> next;
        for (const isa::Instr& in : bundles[b]) {
            const isa::Kind k = in.info().kind;
            if (k == isa::Kind::JumpReg) return path;
            if (k == isa::Kind::Jump) next = static_cast<std::uint32_t>(in.imm);
            else if (ends_flow(k)) return {};
        }
        b = next ? *next : b + 1;
    }
    return {};
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
                else if (ends_flow(k)) stop = true;
            }
        --end;
        if (!loop) continue;
        std::vector<std::uint32_t> path;
        for (std::uint32_t b = sym.value; b <= end; ++b) path.push_back(b);
        out.push_back(analyse_region(bundles, obj, m, sym.name, path));
    }
    // Loops threaded through `jr`: each address-taken label starts one pass (a dispatch body).
    for (const isa::Symbol* sym : address_taken(obj, bundles)) {
        if (!label.empty() && sym->name != label) continue;
        const std::vector<std::uint32_t> path = dispatch_pass(bundles, sym->value);
        if (path.empty()) continue;
        LoopReport r = analyse_region(bundles, obj, m, sym->name, path);
        r.dispatch = true;
        for (std::size_t c = 0; c < path.size();) {
            std::size_t e = c;
            while (e + 1 < path.size() && path[e + 1] == path[e] + 1) ++e;
            r.span += fmt::format("{}{}-{}", r.span.empty() ? "" : ", ", path[c], path[e]);
            c = e + 1;
        }
        for (std::size_t c = 1; c < path.size(); ++c)
            if (path[c] != path[c - 1] + 1)
                for (const isa::Symbol& s : obj.symbols)
                    if (s.kind == isa::SymbolKind::Code && s.value == path[c]) {
                        r.through.push_back(s.name);
                        break;
                    }
        out.push_back(std::move(r));
    }
    if (!label.empty() && out.empty())
        throw std::runtime_error(fmt::format("'{}' is not a loop (a label whose block ends in a branch back to it) nor "
                                             "the start of a jr-dispatched pass", label));
    return out;
}

std::string LoopReport::text() const {
    std::string o;
    if (!dispatch) o = fmt::format("# LOOP {} ({}, bundles {}-{})\n", label, source, first, last);
    else {
        std::string via;
        for (const std::string& t : through) via += (via.empty() ? ", through " : ", ") + t;
        o = fmt::format("# LOOP BODY {} ({}, bundles {}{}): one pass of a jr-dispatched loop, to its jr, "
                        "no exit taken\n", label, source, span, via);
    }
    o += fmt::format("#   bundles {}, achieved II {}, {} operations ({:.2f} per cycle)\n", bundles, ii, ops,
                     static_cast<double>(ops) / ii);
    o += fmt::format("#   resource bound (ResMII)    {}  ({})\n", res_mii, res_binding);
    if (critical.empty()) o += fmt::format("#   recurrence bound (RecMII)  {}  (no recurrence longer than a cycle)\n", rec_mii);
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
                     {"max_live", {{"irf", max_live[0]}, {"fprf", max_live[1]}}},
                     {"kind", dispatch ? "dispatch body" : "loop"}, {"through", through}};
    if (dispatch) j["bundle_ranges"] = span;
    for (const ResourceUse& u : resources) j["resources"].push_back({{"name", u.name}, {"used", u.used}, {"capacity", u.capacity}});
    for (const Lifetime& l : lifetimes) j["lifetimes"].push_back({{"register", l.reg}, {"cycles", l.cycles}});
    j["reservation_table"] = mrt;
    return j.dump(2);
}

} // namespace nesshi::sched
