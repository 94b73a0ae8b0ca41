#include "pipeline_graph.hpp"

#include "assembler/assembler.hpp"
#include "base/error.hpp"
#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cctype>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <regex>
#include <set>
#include <stdexcept>
#include <tuple>

namespace nesshi::sched::pipe {

// The bytes memory op x touches over the whole loop, [lo, hi), when its base is a known constant
// at entry stepped only by its induction and the trip count is known; nullopt otherwise.
std::optional<std::pair<std::int64_t, std::int64_t>> extent(const Graph& g, int x) {
    const Node& a = g.nodes[static_cast<std::size_t>(x)];
    const auto start = g.entry.find(a.base);
    if (start == g.entry.end() || !g.trip) return std::nullopt;
    const Induction* ind = g.induction_of(a.base);
    for (int k = 0; k < static_cast<int>(g.nodes.size()); ++k)
        if (!ind || k != ind->op)
            for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(k)].instr))
                if (o.write && o.file == isa::RegFile::Int && o.reg == a.base) return std::nullopt;
    const std::int64_t step = ind ? ind->step : 0, after = ind && x > ind->op ? 1 : 0;
    const std::int64_t imm = static_cast<std::int32_t>(a.instr.imm);
    const std::int64_t first = start->second + step * after + imm, last = first + step * std::max<std::int64_t>(*g.trip - 1, 0);
    const std::int64_t lo = std::min(first, last), hi = std::max(first, last) + a.width;
    if (lo < 0 || hi > (std::int64_t{1} << 32)) return std::nullopt; // would wrap: no claim
    return std::pair{lo, hi};
}

// Whether memory ops x (iteration i) and y (iteration i + d) may touch the same bytes.
bool may_alias(const Graph& g, const Region& r, int x, int y, int d) {
    const Node& a = g.nodes[static_cast<std::size_t>(x)];
    const Node& b = g.nodes[static_cast<std::size_t>(y)];
    if (a.base != b.base) {
        for (auto [p, q] : r.noalias)
            if ((p == a.base && q == b.base) || (p == b.base && q == a.base)) return false;
        if (g.trip && *g.trip == 0) return false;
        const auto ex = extent(g, x), ey = extent(g, y); // e.g. two arrays at known labels, a known count
        return !(ex && ey && (ex->second <= ey->first || ey->second <= ex->first));
    }
    const Induction* ind = g.induction_of(a.base);
    if (!ind) {
        // A base the loop writes other than by an induction step (a virtual register is renamed
        // every iteration; a physical one may be loaded or computed): its value in another
        // iteration is unknown, and in this one it is the same only when no write of it lies
        // between the two ops (an op reads before its own write lands).
        std::vector<int> writers;
        for (int k = 0; k < static_cast<int>(g.nodes.size()); ++k)
            for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(k)].instr))
                if (o.write && o.file == isa::RegFile::Int && o.reg == a.base) writers.push_back(k);
        if (!writers.empty()) {
            if (d > 0) return true;
            const int lo = std::min(x, y), hi = std::max(x, y);
            if (std::any_of(writers.begin(), writers.end(), [&](int w) { return lo <= w && w < hi; })) return true;
        }
    }
    // Same base, not stepped: the same addresses every iteration.
    const std::int64_t step = ind ? ind->step : 0;
    auto addr = [&](int op, const Node& n, int iter) {
        const bool after = ind && op > ind->op; // the op sees the base after this iteration's step
        return step * (iter + (after ? 1 : 0)) + static_cast<std::int64_t>(static_cast<std::int32_t>(n.instr.imm));
    };
    const std::int64_t ax = addr(x, a, 0), ay = addr(y, b, d);
    return ax < ay + b.width && ay < ax + a.width;
}

// Whether op i of a while loop has an effect a discarded iteration must not have: a store, a
// FIFO word, a load whose base is not declared `.speculate` (it could fault past the end), or a
// write of a physical register other than an induction (the exit path corrects inductions).
bool side_effect(const Graph& g, int i, const std::function<bool(int, isa::RegFile, int)>& is_virtual) {
    const Node& nd = g.nodes[static_cast<std::size_t>(i)];
    const isa::Kind k = nd.instr.info().kind;
    if (k == isa::Kind::Store || k == isa::Kind::Send || k == isa::Kind::Recv) return true;
    if (k == isa::Kind::Load && !nd.speculative) return true;
    for (const isa::RegOperand& o : isa::register_operands(nd.instr))
        if (o.write && !is_virtual(i, o.file, o.reg) && !(o.file == isa::RegFile::Int && g.induction_of(o.reg))) return true;
    return false;
}

// Speculation that is safe by construction: no side effect issues before every earlier exit test
// has been decided. Iteration i's exit test precedes the side effects of iteration i + 1 (and so
// of every later one), and those of iteration i written after the test. One bundle later: the
// ops in the bundle of a taken branch still execute.
void add_exit_edges(Graph& g, const Region& r, const std::function<bool(int, isa::RegFile, int)>& is_virtual) {
    for (int i = 0; i < static_cast<int>(g.nodes.size()); ++i) {
        if (i == r.exit_op || !side_effect(g, i, is_virtual)) continue;
        g.ddg.edges.push_back({r.exit_op, i, 1, 1, DepKind::Exit, "exit before a later side effect"});
        if (i > r.exit_op) g.ddg.edges.push_back({r.exit_op, i, 1, 0, DepKind::Exit, "exit before a side effect after it"});
    }
    // A value the exit path hands out (.carry, .liveout) has landed when the exit is taken: the
    // exiting iteration's when it is written before the test, else the previous iteration's.
    auto landed = [&](const std::string& name) {
        const int def = r.virtuals[static_cast<std::size_t>(r.virtual_index.at(name))].def;
        g.ddg.edges.push_back({def, r.exit_op, g.nodes[static_cast<std::size_t>(def)].latency, def < r.exit_op ? 0 : 1,
                               DepKind::Exit, "live out " + name});
    };
    for (const auto& c : r.carry) landed(c.first);
    for (const auto& l : r.liveout) landed(l.first);
}

Graph build_graph(const Region& r, const std::vector<isa::Instr>& instrs, const isa::Machine& m,
                  const std::vector<OpVirtuals>& op_virtuals, const std::map<int, std::int64_t>& entry) {
    Graph g;
    g.entry = entry;
    if (!r.is_while)
        if (const auto t = entry.find(r.trip_reg); t != entry.end()) g.trip = t->second;
    const int n = static_cast<int>(instrs.size());
    g.ddg.nodes = n;
    for (int i = 0; i < n; ++i) {
        Node nd;
        nd.instr = instrs[static_cast<std::size_t>(i)];
        const isa::OpInfo& info = nd.instr.info();
        nd.latency = static_cast<int>(m.latency_of(info));
        nd.mem = info.kind == isa::Kind::Load || info.kind == isa::Kind::Store;
        nd.store = info.kind == isa::Kind::Store;
        nd.width = info.mem_bytes ? info.mem_bytes : 4;
        if (nd.mem) nd.base = nd.instr.rs1;
        g.nodes.push_back(nd);
    }
    // The virtual an operand register of op i stands for (placeholders may be shared by virtuals
    // whose lifetimes do not meet, never within one op), or -1 for a physical register.
    auto virtual_of = [&](int i, isa::RegFile f, int reg) {
        const OpVirtuals& ov = op_virtuals[static_cast<std::size_t>(i)];
        const auto v = ov.find({static_cast<int>(f), reg});
        return v == ov.end() ? -1 : v->second;
    };
    auto is_virtual = [&](int i, isa::RegFile f, int reg) { return virtual_of(i, f, reg) >= 0; };
    for (int i = 0; i < n; ++i) {
        Node& nd = g.nodes[static_cast<std::size_t>(i)];
        if (nd.instr.info().kind != isa::Kind::Load) continue;
        const int v = virtual_of(i, isa::RegFile::Int, nd.base);
        nd.speculative = v >= 0 ? r.speculate_virtual.count(r.virtuals[static_cast<std::size_t>(v)].name) != 0
                                : r.speculate.count(nd.base) != 0;
    }
    // Induction registers: a physical integer register whose one write is `addi r, r, C`.
    std::map<int, std::vector<int>> int_defs;
    for (int i = 0; i < n; ++i)
        for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(i)].instr))
            if (o.write && o.file == isa::RegFile::Int && !is_virtual(i, o.file, o.reg)) int_defs[o.reg].push_back(i);
    for (auto& [reg, defs] : int_defs) {
        const isa::Instr& in = g.nodes[static_cast<std::size_t>(defs[0])].instr;
        if (defs.size() == 1 && in.info().mnemonic == "addi" && in.rd == in.rs1 && reg != r.trip_reg)
            g.inductions.push_back({reg, defs[0], static_cast<std::int32_t>(in.imm)});
    }
    for (Node& nd : g.nodes)
        if (nd.mem && g.induction_of(nd.base)) nd.adjusted = true;

    // Register dependences, per register: every read depends on the write it sees (this
    // iteration's or the previous one's), must issue no later than the next write (the exposed
    // pipeline: no read of an old value once a newer write is in flight), and writes land in order.
    struct Access {
        int op;
        bool write;
    };
    // Keyed (file, register, virtual or -1): in register order, and placeholders shared by
    // virtuals (placeholder_registers) apart.
    using Key = std::tuple<int, int, int>;
    auto key_of = [&](int i, const isa::RegOperand& o) { return Key{static_cast<int>(o.file), o.reg, virtual_of(i, o.file, o.reg)}; };
    std::map<Key, std::vector<Access>> by_reg;
    for (int i = 0; i < n; ++i) {
        const Node& nd = g.nodes[static_cast<std::size_t>(i)];
        const isa::RegOperands ops = isa::register_operands(nd.instr);
        for (const isa::RegOperand& o : ops) // reads first: an op reads before its own write lands
            if (!o.write && !(nd.adjusted && o.base)) // only the base: a data operand keeps its edges
                by_reg[key_of(i, o)].push_back({i, false});
        for (const isa::RegOperand& o : ops)
            if (o.write) by_reg[key_of(i, o)].push_back({i, true});
    }
    for (const auto& [key, acc] : by_reg) {
        const auto [file, reg, v] = key;
        const bool virt = v >= 0;
        const std::string name = virt ? r.virtuals[static_cast<std::size_t>(v)].name : reg_name(static_cast<isa::RegFile>(file), reg);
        std::vector<int> writes;
        for (const Access& a : acc)
            if (a.write) writes.push_back(a.op);
        if (writes.empty()) continue; // read-only in the loop: live in, no constraint
        const int nw = static_cast<int>(writes.size());
        auto lat = [&](int op) { return g.nodes[static_cast<std::size_t>(op)].latency; };
        for (std::size_t ai = 0; ai < acc.size(); ++ai) {
            const Access& a = acc[ai];
            if (a.write) continue;
            // The write it sees: the last write before it in body order, else the last of the
            // previous iteration.
            int seen = -1, dist = 0;
            for (std::size_t k = 0; k < ai; ++k)
                if (acc[k].write) seen = acc[k].op;
            if (seen < 0) seen = writes.back(), dist = 1;
            if (!(seen == a.op && dist == 0)) g.ddg.edges.push_back({seen, a.op, lat(seen), dist, DepKind::True, "true " + name});
            if (virt) continue; // renamed: its old value is never overwritten too early
            // The next write after it: must not issue before this read.
            int next = -1, ndist = 0;
            for (std::size_t k = ai + 1; k < acc.size(); ++k)
                if (acc[k].write) {
                    next = acc[k].op;
                    break;
                }
            if (next < 0) next = writes.front(), ndist = 1;
            if (next != a.op || ndist != 0) g.ddg.edges.push_back({a.op, next, 0, ndist, DepKind::Anti, "anti " + name});
        }
        if (!virt)
            for (int k = 0; k < nw; ++k) { // output: writes land in program order
                const int from = writes[static_cast<std::size_t>(k)];
                const int to = writes[static_cast<std::size_t>((k + 1) % nw)];
                const int dist = k + 1 == nw ? 1 : 0;
                if (from == to && dist == 1 && nw == 1) continue; // one write per iteration lands in order
                // Landing after is not enough: the next write must also issue after (the
                // assembler and the checked ISS order writes by issue, so a longer write hoisted
                // above a dead shorter one would be the earlier write and land last).
                g.ddg.edges.push_back({from, to, std::max(lat(from) - lat(to) + 1, 1), dist, DepKind::Output, "output " + name});
            }
    }
    // Memory: between a store and any other access that may touch the same bytes, in both
    // directions and at every distance up to kMaxMemoryDistance; one bundle apart at least.
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y) {
            const Node& a = g.nodes[static_cast<std::size_t>(x)];
            const Node& b = g.nodes[static_cast<std::size_t>(y)];
            if (!a.mem || !b.mem || (!a.store && !b.store)) continue;
            for (int d = x < y ? 0 : 1; d <= kMaxMemoryDistance; ++d)
                if (may_alias(g, r, x, y, d)) {
                    std::string why = a.store ? (b.store ? "memory output" : "memory true") : "memory anti";
                    if (a.base != b.base) why += fmt::format(", bases r{} and r{} may alias", a.base, b.base);
                    g.ddg.edges.push_back({x, y, 1, d, DepKind::Memory, why});
                    break; // the smallest distance binds most
                }
        }
    // FIFO words of one channel keep their order.
    std::map<std::uint32_t, std::vector<int>> fifo;
    for (int i = 0; i < n; ++i) {
        const isa::Kind k = g.nodes[static_cast<std::size_t>(i)].instr.info().kind;
        if (k == isa::Kind::Recv || k == isa::Kind::Send)
            fifo[g.nodes[static_cast<std::size_t>(i)].instr.imm * 2 + (k == isa::Kind::Send)].push_back(i);
    }
    for (const auto& [ch, ops] : fifo)
        for (std::size_t k = 0; k < ops.size(); ++k) {
            const bool wrap = k + 1 == ops.size();
            if (wrap && ops.size() == 1) {
                g.ddg.edges.push_back({ops[k], ops[k], 1, 1, DepKind::Fifo, "fifo order"});
                continue;
            }
            g.ddg.edges.push_back({ops[k], ops[(k + 1) % ops.size()], 1, wrap ? 1 : 0, DepKind::Fifo, "fifo order"});
        }
    if (r.is_while) add_exit_edges(g, r, is_virtual);
    return g;
}

// The values the virtual and physical registers carry from op to op (the true edges, one value
// per writer and register), for stage scheduling.
std::vector<StageValue> stage_values(const Graph& g) {
    std::map<std::pair<int, std::string>, StageValue> by;
    for (const Edge& e : g.ddg.edges) {
        if (e.kind != DepKind::True) continue;
        StageValue& v = by[{e.from, e.why}];
        v.def = e.from;
        v.latency = g.nodes[static_cast<std::size_t>(e.from)].latency;
        v.uses.emplace_back(e.to, e.distance);
    }
    std::vector<StageValue> out;
    for (auto& [key, v] : by) out.push_back(std::move(v));
    return out;
}

// The circuit that sets the RecMII, op by op with each edge's latency and why it is there, e.g.
// "flw (line 11) -[2: true %x]-> fmul (line 12) ... : 9 cycles over 1 iteration"; "" when no
// circuit binds above 1.
std::string critical_circuit(const Graph& g, const Region& r, const std::vector<int>& circuit) {
    if (circuit.empty()) return "";
    std::string out;
    int latency = 0, distance = 0;
    for (int k : circuit) {
        const Edge& e = g.ddg.edges[static_cast<std::size_t>(k)];
        const SrcOp& op = r.ops[static_cast<std::size_t>(e.from)];
        out += fmt::format("{} (line {}) -[{}: {}]-> ", op.mnemonic, op.line, e.latency, e.why);
        latency += e.latency;
        distance += e.distance;
    }
    const SrcOp& first = r.ops[static_cast<std::size_t>(g.ddg.edges[static_cast<std::size_t>(circuit.front())].from)];
    return out + fmt::format("{} (line {}): {} cycles over {} iteration{}", first.mnemonic, first.line, latency, distance,
                             distance == 1 ? "" : "s");
}

// When the RecMII's circuit runs through memory edges between two base registers that may alias
// (no `.noalias` for them), what declaring them apart would give: "`.noalias r1, r2` (if the
// arrays never overlap) removes it: RecMII 1"; "" otherwise.
std::string alias_hint(const Graph& g, const std::vector<int>& circuit) {
    std::set<std::pair<int, int>> pairs;
    auto apart = [](const Edge& e) { return e.kind == DepKind::Memory && e.why.find(" may alias") != std::string::npos; };
    for (int k : circuit) {
        const Edge& e = g.ddg.edges[static_cast<std::size_t>(k)];
        if (!apart(e)) continue;
        const int a = g.nodes[static_cast<std::size_t>(e.from)].base, b = g.nodes[static_cast<std::size_t>(e.to)].base;
        pairs.insert({std::min(a, b), std::max(a, b)});
    }
    if (pairs.empty()) return "";
    Ddg kept{g.ddg.nodes, {}}; // every edge but the memory ones between those bases
    for (const Edge& e : g.ddg.edges) {
        const int a = g.nodes[static_cast<std::size_t>(e.from)].base, b = g.nodes[static_cast<std::size_t>(e.to)].base;
        if (!(apart(e) && pairs.count({std::min(a, b), std::max(a, b)}))) kept.edges.push_back(e);
    }
    std::vector<std::string> lines;
    for (auto [a, b] : pairs) lines.push_back(fmt::format(".noalias r{}, r{}", a, b));
    return fmt::format("the circuit's memory edge{} may alias: `{}` (if those arrays never overlap) give{} RecMII {}",
                       pairs.size() == 1 ? "" : "s", fmt::join(lines, "` and `"), pairs.size() == 1 ? "s" : "",
                       kept.rec_mii());
}


} // namespace nesshi::sched::pipe
