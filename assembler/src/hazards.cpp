// Latency-hazard analysis (see hazards.hpp).
#include "hazards.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

namespace nesshi::assembler {

namespace {

struct Pending {
    uint8_t file;
    uint8_t reg;
    uint32_t k;     // cycles from this bundle's issue until the value lands (>= 1)
    uint32_t op;    // global op id of the producer
    auto key() const { return std::tie(file, reg, k, op); }
    bool operator<(const Pending& o) const { return key() < o.key(); }
    bool operator==(const Pending& o) const { return key() == o.key(); }
};
using State = std::vector<Pending>; // sorted, unique

struct RegAccess {
    isa::RegFile file;
    uint8_t reg;
};

char prefix(isa::RegFile f) { return f == isa::RegFile::Int ? 'r' : 'f'; }

void accesses(const isa::Instr& in, std::vector<RegAccess>& reads, std::vector<RegAccess>& writes) {
    for (const isa::RegOperand& r : isa::register_operands(in)) (r.write ? writes : reads).push_back({r.file, r.reg});
}

struct Edge {
    size_t to;
    uint32_t delay;
};

class Analysis {
  public:
    Analysis(const std::vector<PlacedBundle>& b, const isa::Machine& m, Diagnostics& d)
        : bundles_(b), m_(m), diags_(d) {
        for (size_t i = 0; i < b.size(); ++i)
            for (size_t j = 0; j < b[i].rec->ops.size(); ++j) ops_.push_back({i, j});
        build_edges();
    }

    void run() {
        size_t n = bundles_.size() + 1; // the bundles and the indirect-jump hub
        in_.assign(n, {});
        std::vector<bool> queued(n, true);
        std::vector<size_t> work;
        for (size_t i = n; i-- > 0;) work.push_back(i);
        while (!work.empty()) {
            size_t b = work.back();
            work.pop_back();
            queued[b] = false;
            for (const Edge& e : edges_[b]) {
                State out = transfer(b, e.delay);
                if (merge(in_[e.to], out) && !queued[e.to]) {
                    queued[e.to] = true;
                    work.push_back(e.to);
                }
            }
        }
        for (size_t b = 0; b + 1 < n; ++b) report(b);
    }

  private:
    const isa::Instr& instr(uint32_t op) const { return op_rec(op).instr; }
    const OpRec& op_rec(uint32_t op) const { return bundles_[ops_[op].first].rec->ops[ops_[op].second]; }
    uint32_t first_op(size_t b) const {
        return uint32_t(std::lower_bound(ops_.begin(), ops_.end(), std::pair<size_t, size_t>{b, 0}) - ops_.begin());
    }

    // Indirect jumps go through one hub node (index n): every `jr` has an edge to the hub, the
    // hub one to every return point and code label. The state reaching a target is the union over
    // the jumps either way, but the edges are #jr + #targets instead of #jr x #targets (20,000
    // `Lk: jr r1` lines made 400 million edges).
    size_t hub() const { return bundles_.size(); }

    void build_edges() {
        size_t n = bundles_.size();
        uint32_t penalty = m_.branch_penalty;
        std::vector<size_t> indirect; // return points and code labels
        for (size_t b = 0; b + 1 < n; ++b)
            for (const auto& o : bundles_[b].rec->ops)
                if (o.instr.info().kind == isa::Kind::JumpLink) indirect.push_back(b + 1);
        edges_.assign(n + 1, {});
        for (size_t b = 0; b < n; ++b) {
            bool ends = false;
            for (const auto& o : bundles_[b].rec->ops) {
                const isa::Instr& in = o.instr;
                switch (in.info().kind) {
                case isa::Kind::Branch:
                    if (in.imm < n) edges_[b].push_back({in.imm, 1 + penalty});
                    break;
                case isa::Kind::Jump:
                case isa::Kind::JumpLink:
                    if (in.imm < n) edges_[b].push_back({in.imm, 1 + penalty});
                    ends = true;
                    break;
                case isa::Kind::JumpReg:
                    jr_.push_back(b);
                    ends = true;
                    break;
                case isa::Kind::Halt: ends = true; break;
                default: break;
                }
            }
            if (!ends && b + 1 < n) edges_[b].push_back({b + 1, 1});
            if (!ends && b + 1 == n) falls_off_end = true;
        }
        // The jump's delay is charged on the way in; the hub passes the state on unchanged.
        for (size_t b : jr_) edges_[b].push_back({hub(), 1 + penalty});
        add_indirect_targets(indirect);
    }

public:
    bool falls_off_end = false;

    void add_indirect_targets(const std::vector<size_t>& targets) {
        if (jr_.empty()) return;
        for (size_t t : targets)
            if (t < bundles_.size()) hub_targets_.push_back(t);
        std::sort(hub_targets_.begin(), hub_targets_.end());
        hub_targets_.erase(std::unique(hub_targets_.begin(), hub_targets_.end()), hub_targets_.end());
        edges_[hub()].clear();
        for (size_t t : hub_targets_) edges_[hub()].push_back({t, 0});
    }

private:
    State transfer(size_t b, uint32_t delay) const {
        if (b == hub()) return in_[b];
        State out;
        for (const Pending& p : in_[b])
            if (p.k > delay) out.push_back({p.file, p.reg, p.k - delay, p.op});
        uint32_t op = first_op(b);
        for (const auto& o : bundles_[b].rec->ops) {
            std::vector<RegAccess> r, w;
            accesses(o.instr, r, w);
            uint32_t lat = m_.latency_of(o.instr.info());
            for (const RegAccess& a : w)
                if (lat > delay) out.push_back({uint8_t(a.file), a.reg, lat - delay, op});
            ++op;
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    static bool merge(State& into, const State& add) {
        State merged;
        std::set_union(into.begin(), into.end(), add.begin(), add.end(), std::back_inserter(merged));
        if (merged.size() == into.size()) return false;
        into = std::move(merged);
        return true;
    }

    // A producer at or after the bundle it reaches can only reach it around a back edge.
    const char* back_edge(uint32_t producer, size_t b) const {
        return ops_[producer].first >= b ? " (around a back edge)" : "";
    }

    void report(size_t b) {
        const State& s = in_[b];
        uint32_t op = first_op(b);
        for (const auto& o : bundles_[b].rec->ops) {
            std::vector<RegAccess> reads, writes;
            accesses(o.instr, reads, writes);
            std::set<std::pair<int, int>> seen;
            for (const RegAccess& a : reads) {
                if (!seen.insert({int(a.file), a.reg}).second) continue;
                // One error per producer still in flight: every path that reaches this read with
                // a pending write is reported, so fixing one does not uncover the next.
                std::set<uint32_t> producers;
                for (const Pending& p : s) {
                    if (p.file != uint8_t(a.file) || p.reg != a.reg || !producers.insert(p.op).second) continue;
                    const isa::Instr& pin = instr(p.op);
                    uint32_t lat = m_.latency_of(pin.info());
                    Diagnostic& d = diags_.error(
                        o.loc, fmt::format("{}{} is read before its new value lands: '{}' was issued {} "
                                           "cycle{} earlier{} and has latency {}", prefix(a.file), a.reg,
                                           pin.info().mnemonic, lat - p.k, lat - p.k == 1 ? "" : "s",
                                           back_edge(p.op, b), lat));
                    Diagnostics::note(d, op_rec(p.op).loc,
                                      fmt::format("{}{} is written here; the result lands in cycle +{}",
                                                  prefix(a.file), a.reg, lat));
                }
            }
            uint32_t lat = m_.latency_of(o.instr.info());
            for (const RegAccess& a : writes) write_order(b, o, lat, a);
            ++op;
        }
        write_ports(b);
    }

    // A write landing before, or in the same cycle as, an earlier-issued write to its register that
    // is still in flight: the older value would land over the newer one, or both in one cycle. One
    // error per earlier producer, on the path where it lands latest (the most nops to fix); the
    // same-cycle message (once per write) only when no earlier write lands after this one, so one
    // collision is never reported twice. Earlier-issued includes an op of this bundle in a lower
    // slot: the order in which the ISS issues a bundle's ops.
    void write_order(size_t b, const OpRec& o, uint32_t lat, const RegAccess& a) {
        std::map<uint32_t, uint32_t> latest; // producer -> cycles until it lands, at most
        for (const Pending& p : in_[b])
            if (p.file == uint8_t(a.file) && p.reg == a.reg) latest[p.op] = std::max(latest[p.op], p.k);
        const std::string reg = fmt::format("{}{}", prefix(a.file), a.reg);
        bool reported = false;
        for (const auto& [producer, k] : latest) {
            if (k <= lat) continue;
            const isa::Instr& pin = instr(producer);
            uint32_t plat = m_.latency_of(pin.info());
            Diagnostic& d = diags_.error(
                o.loc, fmt::format("{} is written before an earlier write to it lands: this result lands in cycle "
                                   "+{}, the earlier '{}'{} in cycle +{}", reg, lat, pin.info().mnemonic,
                                   back_edge(producer, b), k));
            Diagnostics::note(d, op_rec(producer).loc,
                              fmt::format("earlier write of {}: issued {} cycle{} before, latency {}, lands in cycle +{}",
                                          reg, plat - k, plat - k == 1 ? "" : "s", plat, k));
            reported = true;
        }
        for (const OpRec& e : bundles_[b].rec->ops) { // this bundle: the ISS issues by slot
            uint32_t elat = m_.latency_of(e.instr.info());
            if (&e == &o || e.instr.slot >= o.instr.slot || elat <= lat) continue;
            std::vector<RegAccess> er, ew;
            accesses(e.instr, er, ew);
            for (const RegAccess& w : ew)
                if (w.file == a.file && w.reg == a.reg) {
                    Diagnostic& d = diags_.error(
                        o.loc, fmt::format("{} is written before an earlier write to it lands: this result lands in "
                                           "cycle +{}, the '{}' of a lower slot of this bundle in cycle +{}",
                                           reg, lat, e.instr.info().mnemonic, elat));
                    Diagnostics::note(d, e.loc, fmt::format("earlier write of {}: slot {}, latency {}, lands in cycle +{}",
                                                            reg, m_.slots[e.instr.slot].name, elat, elat));
                    reported = true;
                }
        }
        if (reported) return;
        for (const Pending& p : in_[b])
            if (p.file == uint8_t(a.file) && p.reg == a.reg && p.k == lat) {
                Diagnostic& d = diags_.error(
                    o.loc, fmt::format("{} is written twice in one cycle: this result and an earlier '{}'{} both "
                                       "land in cycle +{}", reg, instr(p.op).info().mnemonic, back_edge(p.op, b), lat));
                Diagnostics::note(d, op_rec(p.op).loc, fmt::format("other write of {}", reg));
                return;
            }
    }

    // Writes landing in one cycle, this bundle's plus those still in flight, against the ports.
    void write_ports(size_t b) {
        const State& s = in_[b];
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            uint32_t ports = m_.regs[size_t(f)].write_ports;
            std::set<uint32_t> reported;
            uint32_t count_by_lat[64] = {};
            for (const auto& o : bundles_[b].rec->ops) {
                std::vector<RegAccess> reads, writes;
                accesses(o.instr, reads, writes);
                uint32_t lat = m_.latency_of(o.instr.info());
                for (const RegAccess& a : writes) {
                    if (int(a.file) != f || lat >= 64) continue;
                    uint32_t earlier = 0;
                    const Pending* first = nullptr;
                    // Pending writes merge the paths into this bundle; writes to one register
                    // landing in one cycle come from different paths (on one path they would be a
                    // duplicate write, reported where it arises), so each register counts once.
                    std::set<uint32_t> registers;
                    for (const Pending& p : s)
                        if (p.file == f && p.k == lat && registers.insert(p.reg).second) {
                            ++earlier;
                            if (!first) first = &p;
                        }
                    if (earlier == 0) continue;
                    uint32_t total = earlier + ++count_by_lat[lat];
                    if (total <= ports || !reported.insert(lat).second) continue;
                    Diagnostic& d = diags_.error(
                        o.loc, fmt::format("{} writes land in one cycle: {} has {} {} write ports "
                                           "(this result lands in cycle +{} together with {} issued earlier{})",
                                           total, m_.name, ports, isa::kRegFileNames[size_t(f)], lat, earlier,
                                           *back_edge(first->op, b) ? ", around a back edge" : ""));
                    Diagnostics::note(d, op_rec(first->op).loc,
                                      fmt::format("'{}' issued earlier lands in the same cycle",
                                                  instr(first->op).info().mnemonic));
                }
            }
        }
    }

    const std::vector<PlacedBundle>& bundles_;
    const isa::Machine& m_;
    Diagnostics& diags_;
    std::vector<std::pair<size_t, size_t>> ops_; // global op id -> (bundle, op)
    std::vector<std::vector<Edge>> edges_;
    std::vector<size_t> jr_;
    std::vector<size_t> hub_targets_;
    std::vector<State> in_;
};

} // namespace

void check_hazards(const std::vector<PlacedBundle>& bundles, const isa::Machine& m, Diagnostics& diags,
                   const std::vector<size_t>& code_labels) {
    Analysis a(bundles, m, diags);
    a.add_indirect_targets(code_labels);
    a.run();
    if (a.falls_off_end)
        diags.warning(bundles.back().rec->loc, "execution can run past the last bundle (end the code with "
                                               "'halt' or a jump)");
}

} // namespace nesshi::assembler
