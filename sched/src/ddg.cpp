// The dependence graph's algorithms and the builders of the block scheduler's and the reports'
// graphs (see ddg.hpp); the pipeliner builds its own in pipeline_graph.cpp.
#include "sched/ddg.hpp"

#include "isa/ops.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

namespace nesshi::sched {

namespace {

// Longest-path relaxation with edge weights latency x den - num x distance (the II num / den);
// returns the edge of the last relaxation of a round past n (a positive circuit's), or -1 when
// the lengths settle. `pred`: each node's last relaxing edge.
int relax(const Ddg& g, std::int64_t num, std::int64_t den, std::vector<int>* pred) {
    const std::size_t n = static_cast<std::size_t>(g.nodes);
    std::vector<std::int64_t> dist(n, 0);
    if (pred) pred->assign(n, -1);
    int last = -1;
    for (std::size_t round = 0; round <= n; ++round) {
        last = -1;
        for (std::size_t k = 0; k < g.edges.size(); ++k) {
            const Dep& e = g.edges[k];
            const std::int64_t w = e.latency * den - num * e.distance;
            const std::size_t from = static_cast<std::size_t>(e.from), to = static_cast<std::size_t>(e.to);
            if (dist[from] + w > dist[to]) {
                dist[to] = dist[from] + w;
                if (pred) (*pred)[to] = static_cast<int>(k);
                last = static_cast<int>(k);
            }
        }
        if (last < 0) return -1;
    }
    return last;
}

// A circuit positive at the II num / den, as edge indices in order; empty when none is.
std::vector<int> positive_circuit(const Ddg& g, std::int64_t num, std::int64_t den) {
    std::vector<int> pred;
    const int e = relax(g, num, den, &pred);
    if (e < 0) return {};
    // Walk predecessors n times to land inside the circuit, then collect it.
    int v = g.edges[static_cast<std::size_t>(e)].to;
    for (int k = 0; k < g.nodes; ++k) v = g.edges[static_cast<std::size_t>(pred[static_cast<std::size_t>(v)])].from;
    std::vector<int> circuit;
    int u = v;
    do {
        const int pe = pred[static_cast<std::size_t>(u)];
        circuit.push_back(pe);
        u = g.edges[static_cast<std::size_t>(pe)].from;
    } while (u != v && circuit.size() <= g.edges.size());
    std::reverse(circuit.begin(), circuit.end());
    return circuit;
}

} // namespace

bool Ddg::admits(int ii) const { return relax(*this, ii, 1, nullptr) < 0; }

int Ddg::rec_mii() const {
    // No II admits a circuit of positive latency over distance 0; the builders never make one
    // (its ops would each wait for the other in one iteration), so this bound is a safeguard.
    std::int64_t most = 1;
    for (const Dep& e : edges) most += std::max(e.latency, 0);
    int ii = 1;
    while (!admits(ii)) {
        if (++ii > most) throw std::logic_error("Ddg::rec_mii: a circuit of positive latency over no iteration");
    }
    return ii;
}

std::vector<int> Ddg::circuit_above(int ii) const { return positive_circuit(*this, ii, 1); }

std::vector<int> Ddg::critical() const {
    const int rec = rec_mii();
    return rec <= 1 ? std::vector<int>{} : circuit_above(rec - 1);
}

std::vector<int> Ddg::max_ratio_circuit() const {
    // Each circuit found beats the ratio of the one before (Lawler's iteration): finitely many.
    std::vector<int> best = positive_circuit(*this, 0, 1);
    while (!best.empty()) {
        const CycleRatio r = ratio(best);
        if (r.distance == 0) break; // no II admits it; the builders never make one
        std::vector<int> better = positive_circuit(*this, r.latency, r.distance);
        if (better.empty()) break;
        best = std::move(better);
    }
    return best;
}

CycleRatio Ddg::ratio(std::span<const int> circuit) const {
    CycleRatio r;
    for (const int k : circuit) {
        r.latency += edges[static_cast<std::size_t>(k)].latency;
        r.distance += edges[static_cast<std::size_t>(k)].distance;
    }
    return r;
}

std::vector<int> Ddg::longest_paths(int ii, bool out) const {
    std::vector<int> len(static_cast<std::size_t>(nodes), 0);
    for (int iter = 0; iter < nodes + 1; ++iter) { // the fixed point when the II admits the recurrences
        bool changed = false;
        for (const Dep& e : edges) {
            if (e.from == e.to) continue;
            const std::size_t near = static_cast<std::size_t>(out ? e.from : e.to), far = static_cast<std::size_t>(out ? e.to : e.from);
            const int l = len[far] + e.latency - e.distance * ii;
            if (l > len[near]) {
                len[near] = l;
                changed = true;
            }
        }
        if (!changed) break;
    }
    return len;
}

std::vector<std::vector<int>> Ddg::edges_into() const {
    std::vector<std::vector<int>> into(static_cast<std::size_t>(nodes));
    for (std::size_t k = 0; k < edges.size(); ++k) into[static_cast<std::size_t>(edges[k].to)].push_back(static_cast<int>(k));
    return into;
}

Ddg block_ddg(const isa::Machine& m, std::span<const isa::Instr> ops, int grace) {
    using Reg = std::pair<int, int>; // (file, register)
    const int n = static_cast<int>(ops.size());
    std::vector<int> latency(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) latency[static_cast<std::size_t>(j)] = static_cast<int>(m.latency_of(ops[static_cast<std::size_t>(j)].info()));
    Ddg g;
    g.nodes = n;
    auto add = [&](int from, int to, int lat, DepKind kind) { g.edges.push_back({from, to, lat, 0, kind}); };
    std::map<Reg, int> last_write;
    std::map<Reg, std::vector<int>> readers; // since the last write
    std::optional<int> last_store;
    std::vector<int> loads; // since the last store
    std::map<std::uint32_t, int> channel_last;
    for (int j = 0; j < n; ++j) {
        const isa::Instr& in = ops[static_cast<std::size_t>(j)];
        const isa::OpInfo& info = in.info();
        const int lat = latency[static_cast<std::size_t>(j)];
        std::optional<Reg> dst;
        std::vector<Reg> srcs; // every register read, repeats included
        for (const isa::RegOperand& o : isa::register_operands(in)) {
            const Reg reg{static_cast<int>(o.file), o.reg};
            if (o.write) dst = reg;
            else srcs.push_back(reg);
        }
        std::optional<std::uint32_t> channel; // FIFO ops: both directions share the order
        if (info.kind == isa::Kind::Recv || info.kind == isa::Kind::Send) channel = in.imm;
        const bool barrier = info.cls == isa::OpClass::Branch || (info.cls == isa::OpClass::Misc && info.kind != isa::Kind::Nop);

        for (const Reg& s : srcs)
            if (auto w = last_write.find(s); w != last_write.end()) add(w->second, j, latency[static_cast<std::size_t>(w->second)], DepKind::True);
        if (dst) {
            for (int i : readers[*dst]) // the write lands after the read issues
                if (i != j) add(i, j, 1 - lat, DepKind::Anti);
            if (auto w = last_write.find(*dst); w != last_write.end())
                add(w->second, j, latency[static_cast<std::size_t>(w->second)] + 1 - lat, DepKind::Output);
        }
        if (info.cls == isa::OpClass::Load && last_store) add(*last_store, j, 1, DepKind::Memory);
        if (info.cls == isa::OpClass::Store) {
            for (int i : loads) add(i, j, 0, DepKind::Memory);
            if (last_store) add(*last_store, j, 1, DepKind::Memory);
        }
        if (channel)
            if (auto c = channel_last.find(*channel); c != channel_last.end()) add(c->second, j, 0, DepKind::Fifo);
        if (barrier)
            for (int i = 0; i < j; ++i) add(i, j, std::max(latency[static_cast<std::size_t>(i)] - 1 - grace, 0), DepKind::Order);

        for (const Reg& s : srcs) readers[s].push_back(j);
        if (dst) {
            last_write[*dst] = j;
            readers[*dst].clear();
        }
        if (info.cls == isa::OpClass::Load) loads.push_back(j);
        if (info.cls == isa::OpClass::Store) {
            last_store = j;
            loads.clear();
        }
        if (channel) channel_last[*channel] = j;
    }
    return g;
}

namespace {

std::string reg_name(isa::RegFile f, int r) { return (f == isa::RegFile::Int ? "r" : "f") + std::to_string(r); }

// True register dependences of a scheduled body run every ii cycles: a read sees the write that
// landed last by its cycle, from this pass or an earlier one (its distance).
void add_true_dependences(Ddg& g, std::span<const BodyOp> ops, const std::vector<int>& latency, int ii) {
    for (std::size_t u = 0; u < ops.size(); ++u)
        for (const isa::RegOperand& r : isa::register_operands(ops[u].instr)) {
            if (r.write) continue;
            int best = -1, best_dist = 0;
            std::int64_t best_land = 0;
            for (std::size_t w = 0; w < ops.size(); ++w)
                for (const isa::RegOperand& o : isa::register_operands(ops[w].instr)) {
                    if (!o.write || o.file != r.file || o.reg != r.reg) continue;
                    const std::int64_t land0 = static_cast<std::int64_t>(ops[w].bundle) + latency[w];
                    // the latest pass d >= 0 back whose write has landed when u reads
                    int d = 0;
                    while (land0 - static_cast<std::int64_t>(d) * ii > static_cast<std::int64_t>(ops[u].bundle)) ++d;
                    const std::int64_t land = land0 - static_cast<std::int64_t>(d) * ii;
                    if (best < 0 || land > best_land) best = static_cast<int>(w), best_dist = d, best_land = land;
                }
            if (best >= 0)
                g.edges.push_back({best, static_cast<int>(u), latency[static_cast<std::size_t>(best)], best_dist, DepKind::True,
                                   "true " + reg_name(r.file, r.reg)});
        }
}

// Memory true dependences of a scheduled body run as a loop: a store and a later load (this pass
// or a later one) off the same base register, stepped by a constant `addi` once per pass or not
// at all, that touch common bytes; the smallest distance up to kMaxMemoryDistance. Other pairs
// are not counted: their addresses are not known here.
void add_memory_dependences(Ddg& g, std::span<const BodyOp> ops) {
    auto step_of = [&](int base, int& step_op) -> std::optional<std::int64_t> {
        std::optional<std::int64_t> step = 0;
        step_op = -1;
        for (std::size_t w = 0; w < ops.size(); ++w)
            for (const isa::RegOperand& o : isa::register_operands(ops[w].instr))
                if (o.write && o.file == isa::RegFile::Int && o.reg == base) {
                    const isa::Instr& in = ops[w].instr;
                    if (step_op >= 0 || in.info().mnemonic != "addi" || in.rs1 != in.rd) return std::nullopt;
                    step_op = static_cast<int>(w);
                    step = static_cast<std::int32_t>(in.imm);
                }
        return step;
    };
    // An op sees the base stepped when it issues after the step (a bundle reads its sources at
    // issue, so the step's own bundle sees the old value).
    auto address = [&](std::size_t op, int step_op, std::int64_t step, int pass) {
        const bool after = step_op >= 0 && ops[op].bundle > ops[static_cast<std::size_t>(step_op)].bundle;
        return step * (pass + (after ? 1 : 0)) + static_cast<std::int32_t>(ops[op].instr.imm);
    };
    for (std::size_t st = 0; st < ops.size(); ++st) {
        if (ops[st].instr.info().kind != isa::Kind::Store) continue;
        const int base = ops[st].instr.rs1;
        int step_op = -1;
        const std::optional<std::int64_t> step = step_of(base, step_op);
        if (!step) continue;
        const int sw = ops[st].instr.info().mem_bytes ? ops[st].instr.info().mem_bytes : 4;
        for (std::size_t ld = 0; ld < ops.size(); ++ld) {
            const isa::Instr& l = ops[ld].instr;
            if (l.info().kind != isa::Kind::Load || l.rs1 != base) continue;
            const int lw = l.info().mem_bytes ? l.info().mem_bytes : 4;
            for (int d = ops[ld].bundle > ops[st].bundle ? 0 : 1; d <= kMaxMemoryDistance; ++d) {
                const std::int64_t a = address(st, step_op, *step, 0), b = address(ld, step_op, *step, d);
                if (a < b + lw && b < a + sw) {
                    g.edges.push_back({static_cast<int>(st), static_cast<int>(ld), 1, d, DepKind::Memory,
                                       "memory true r" + std::to_string(base)});
                    break;
                }
            }
        }
    }
}

} // namespace

Ddg scheduled_loop_ddg(const isa::Machine& m, std::span<const BodyOp> ops, int ii) {
    if (ii < 1) throw std::invalid_argument("scheduled_loop_ddg: the II must be at least 1");
    Ddg g;
    g.nodes = static_cast<int>(ops.size());
    std::vector<int> latency;
    for (const BodyOp& o : ops) latency.push_back(static_cast<int>(m.latency_of(o.instr.info())));
    add_true_dependences(g, ops, latency, ii);
    add_memory_dependences(g, ops);
    return g;
}

} // namespace nesshi::sched
