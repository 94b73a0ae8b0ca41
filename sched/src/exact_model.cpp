// The Gecode model of exact_model.hpp. Per op a row r in [0, II) and a stage s >= 0, its issue
// cycle t = II s + r; the branch is fixed in row II - 1. The search branches on rows only: once
// every row is fixed, the dependences are difference constraints on the stages, and at their
// bounds-consistent fixpoint each stage's minimum is a solution (the least stages).
#include "exact_model.hpp"

#include <gecode/int.hh>
#include <gecode/minimodel.hh>
#include <gecode/search.hh>

#include <algorithm>
#include <bit>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <tuple>

namespace nesshi::sched::pipe {
namespace {

using namespace Gecode;

// Longest path out of each op at this II: ops on long paths are ordered first.
std::vector<int> heights(const ModelProblem& p) {
    std::vector<int> h(p.ops.size(), 0);
    for (std::size_t round = 0; round <= p.ops.size(); ++round) {
        bool changed = false;
        for (const ModelEdge& e : p.edges) {
            if (e.from == e.to) continue;
            const int v = e.latency - e.distance * p.ii + h[static_cast<std::size_t>(e.to)];
            if (v > h[static_cast<std::size_t>(e.from)]) h[static_cast<std::size_t>(e.from)] = v, changed = true;
        }
        if (!changed) break;
    }
    return h;
}

class TableSpace : public Space {
  public:
    IntVarArray row, stage, time;

    TableSpace(const ModelProblem& p, BackEdgeRule rule) : ii_(p.ii) {
        const int n = static_cast<int>(p.ops.size());
        const int last = ii_ - 1; // the branch's row
        row = IntVarArray(*this, n, 0, last);
        // No schedule needs more stages than n times the most any one edge asks for.
        int per_edge = 1;
        for (const ModelEdge& e : p.edges) per_edge = std::max(per_edge, (2 * ii_ - 2 + e.latency) / ii_ - e.distance);
        const int most_stages = p.straight ? 0 : n * per_edge + 1;
        stage = IntVarArray(*this, n, 0, most_stages);
        time = IntVarArray(*this, n, 0, most_stages * ii_ + last);
        for (int i = 0; i < n; ++i) linear(*this, IntArgs({1, -ii_, -1}), IntVarArgs({time[i], stage[i], row[i]}), IRT_EQ, 0);
        // A block's results land by its end (so the landings never wrap onto its rows but at 0,
        // where nothing else lands), or by the end of its final jump's bubble: those wrap onto
        // the first rows, where they only count against ports more than they need to.
        if (p.straight)
            for (int i = 0; i < n; ++i) rel(*this, time[i], IRT_LQ, p.latest[static_cast<std::size_t>(i)]);
        // Edge latencies are never negative, so a stage of II + bubble around the back edge asks
        // no more of a dependence than one of II: the edges hold in II alone.
        for (const ModelEdge& e : p.edges) {
            if (e.from == e.to) {
                if (e.latency > e.distance * ii_) fail();
                continue;
            }
            rel(*this, time[e.to] - time[e.from] >= e.latency - e.distance * ii_);
        }
        slots(p);
        ports(p);
        same_register(p);
        flights(p);
        if (rule.apply && p.bubble > 0) back_edge(p, rule.copies);
        if (failed()) return;
        branching(p);
    }

    TableSpace(TableSpace& o) : Space(o), ii_(o.ii_), order_(o.order_) {
        row.update(*this, o.row);
        stage.update(*this, o.stage);
        time.update(*this, o.time);
    }
    Space* copy() override { return new TableSpace(*this); }

    // The restart engine calls this on its root with each solution before it restarts: every
    // solution it returns was refused (an accepted one ends the search), so it is excluded, or
    // a restart could find the same table again.
    void constrain(const Space& last) override {
        const TableSpace& t = static_cast<const TableSpace&>(last);
        BoolVarArgs differs;
        for (int i = 0; i < row.size(); ++i) differs << expr(*this, row[i] != t.row[i].val());
        rel(*this, BOT_OR, differs, 1);
    }

  private:
    int ii_;
    std::vector<int> order_; // branching position -> op

    // The row at or after the op's earliest issue (mod II), the first free one cyclically:
    // short iterations first.
    static int earliest_row(const Space& home, IntVar x, int i) {
        const TableSpace& s = static_cast<const TableSpace&>(home);
        const int op = s.order_[static_cast<std::size_t>(i)];
        const int want = s.time[op].min() % s.ii_;
        for (int k = 0; k < s.ii_; ++k)
            if (x.in((want + k) % s.ii_)) return (want + k) % s.ii_;
        return x.min();
    }

    void branching(const ModelProblem& p) {
        const std::vector<int> h = heights(p);
        order_.resize(p.ops.size());
        std::iota(order_.begin(), order_.end(), 0);
        std::stable_sort(order_.begin(), order_.end(),
                         [&](int a, int b) { return h[static_cast<std::size_t>(a)] > h[static_cast<std::size_t>(b)]; });
        IntVarArgs rows;
        for (int i : order_) rows << row[i];
        // Conflict history (CHB) picks the op; on these tables it decides in milliseconds where a
        // static order by height ran for seconds.
        Gecode::branch(*this, rows, INT_VAR_CHB_SIZE_MAX(), INT_VAL(&TableSpace::earliest_row));
    }

    // Slots: per row, the ops must have a matching into the slots that accept them
    // (isa::assign_slots). By Hall's theorem that is, for every set T of slots, at most |T| ops
    // whose slots all lie in T; one constraint per distinct set of ops, with the smallest T.
    void slots(const ModelProblem& p) {
        const int n = static_cast<int>(p.ops.size());
        struct Bound {
            int size, branch; // |T|, and 1 when the branch's slots lie in T (it takes one in row II - 1)
        };
        std::map<std::vector<int>, Bound> tightest;
        for (std::uint32_t t = 1; t < (1u << p.slot_count); ++t) {
            std::vector<int> within;
            for (int i = 0; i < n; ++i)
                if ((p.ops[static_cast<std::size_t>(i)].slots & ~t) == 0) within.push_back(i);
            if (within.empty()) continue;
            const Bound b{std::popcount(t), p.has_branch && (p.branch.slots & ~t) == 0 ? 1 : 0};
            auto [it, fresh] = tightest.try_emplace(within, b);
            if (!fresh && (b.size < it->second.size || (b.size == it->second.size && b.branch > it->second.branch))) it->second = b;
        }
        for (const auto& [within, b] : tightest) {
            if (static_cast<int>(within.size()) <= b.size - b.branch) continue; // never binds
            std::vector<int> cap(static_cast<std::size_t>(ii_), b.size);
            cap.back() -= b.branch;
            per_row(within, std::vector<int>(within.size(), 1), std::vector<int>(within.size(), 0), cap);
        }
    }

    // Register ports per file: reads in the row an op issues in, writes in the row they land in.
    void ports(const ModelProblem& p) {
        for (std::size_t f = 0; f < p.read_ports.size(); ++f) {
            std::vector<int> ops, uses, shifts;
            for (std::size_t i = 0; i < p.ops.size(); ++i)
                if (p.ops[i].reads[f] > 0) ops.push_back(static_cast<int>(i)), uses.push_back(p.ops[i].reads[f]), shifts.push_back(0);
            std::vector<int> cap(static_cast<std::size_t>(ii_), p.read_ports[f]);
            cap.back() -= p.branch.reads[f];
            if (!ops.empty()) per_row(ops, uses, shifts, cap);
            ops.clear(), uses.clear(), shifts.clear();
            for (std::size_t i = 0; i < p.ops.size(); ++i)
                if (p.ops[i].writes[f] > 0)
                    ops.push_back(static_cast<int>(i)), uses.push_back(p.ops[i].writes[f]), shifts.push_back(p.ops[i].latency);
            cap.assign(static_cast<std::size_t>(ii_), p.write_ports[f]);
            if (!p.straight) cap[static_cast<std::size_t>((ii_ - 1 + p.branch.latency) % ii_)] -= p.branch.writes[f];
            if (!ops.empty()) per_row(ops, uses, shifts, cap);
        }
    }

    // Per row q: the sum of uses[k] over ops[k] whose row + shifts[k] is q (mod II) is at most
    // cap[q]; exactly cap[q] when the uses fill every row (a redundant constraint that prunes).
    void per_row(const std::vector<int>& ops, const std::vector<int>& uses, const std::vector<int>& shifts, const std::vector<int>& cap) {
        const long total = std::accumulate(uses.begin(), uses.end(), 0L), room = std::accumulate(cap.begin(), cap.end(), 0L);
        if (total > room || *std::min_element(cap.begin(), cap.end()) < 0) return fail();
        const bool full = total == room;
        IntVarArgs at; // the row each op uses the resource in
        for (std::size_t k = 0; k < ops.size(); ++k) {
            if (shifts[k] % ii_ == 0) {
                at << row[ops[k]];
                continue;
            }
            IntArgs shifted(ii_);
            for (int q = 0; q < ii_; ++q) shifted[q] = (q + shifts[k]) % ii_;
            IntVar l(*this, 0, ii_ - 1);
            element(*this, shifted, row[ops[k]], l, IPL_DOM);
            at << l;
        }
        if (std::all_of(uses.begin(), uses.end(), [](int u) { return u == 1; })) {
            IntSetArgs counts(ii_);
            IntArgs values(ii_);
            for (int q = 0; q < ii_; ++q) counts[q] = IntSet(full ? cap[static_cast<std::size_t>(q)] : 0, cap[static_cast<std::size_t>(q)]), values[q] = q;
            count(*this, at, counts, values, IPL_DOM);
        } else {
            IntVarArgs load(ii_);
            for (int q = 0; q < ii_; ++q) load[q] = IntVar(*this, full ? cap[static_cast<std::size_t>(q)] : 0, cap[static_cast<std::size_t>(q)]);
            binpacking(*this, load, at, IntArgs(uses));
            // Implied, and binpacking does not see it: a row of cap c holds at most c / w uses of
            // w or more (13 two-register reads never fit 6 rows of 5 read ports: at most 12).
            for (const int w : std::set<int>(uses.begin(), uses.end())) {
                if (w < 2) continue;
                IntVarArgs heavy;
                for (std::size_t k = 0; k < uses.size(); ++k)
                    if (uses[k] >= w) heavy << at[static_cast<int>(k)];
                IntSetArgs most(ii_);
                IntArgs values(ii_);
                for (int q = 0; q < ii_; ++q) most[q] = IntSet(0, cap[static_cast<std::size_t>(q)] / w), values[q] = q;
                count(*this, heavy, most, values, IPL_DOM);
            }
        }
    }

    // Writes of one register with one latency land in distinct rows (the table keeps one write
    // per register and landing cycle), and never where the branch's write of it lands.
    void same_register(const ModelProblem& p) {
        std::map<std::tuple<int, int, int>, std::vector<int>> groups;
        for (std::size_t i = 0; i < p.ops.size(); ++i)
            for (auto [f, reg] : p.ops[i].written) groups[{f, reg, p.ops[i].latency}].push_back(static_cast<int>(i));
        for (const auto& [key, ops] : groups) {
            for (auto [f, reg] : p.branch.written)
                if (std::tuple{f, reg, p.branch.latency} == key)
                    for (int i : ops) rel(*this, row[i], IRT_NQ, ii_ - 1);
            if (ops.size() < 2) continue;
            IntVarArgs rows;
            for (int i : ops) rows << row[i];
            distinct(*this, rows, IPL_DOM);
        }
    }

    // An induction step in flight: its users' rows are not 1 .. latency - 1 after its own (mod II).
    void flights(const ModelProblem& p) {
        for (const ModelFlight& fl : p.flights) {
            if (fl.latency > ii_) return fail();
            TupleSet allowed(2);
            for (int step = 0; step < ii_; ++step)
                for (int use = 0; use < ii_; ++use) {
                    const int d = ((use - step) % ii_ + ii_) % ii_;
                    if (d == 0 || d >= fl.latency) allowed.add(IntArgs({step, use}));
                }
            allowed.finalize();
            for (int u : fl.users) extensional(*this, IntVarArgs({row[fl.step], row[u]}), allowed);
        }
    }

    // The kernel's back edge with a taken-branch bubble (kernel_landings_ok): at each cycle a of
    // a pass where writes of this pass's kernel copies land, they and the writes of the pass
    // before (shifted by the bubble) landing there share the file's write ports. `copies` > 0:
    // a kernel of that many copies; 0: any number from the write depth up. The branch writes no
    // register.
    void back_edge(const ModelProblem& p, int copies) {
        const int bubble = p.bubble, n = static_cast<int>(p.ops.size());
        std::vector<BoolVarArgs> at(static_cast<std::size_t>(n));
        int horizon = 0;
        for (int i = 0; i < n; ++i) {
            at[static_cast<std::size_t>(i)] = BoolVarArgs(*this, ii_, 0, 1);
            channel(*this, at[static_cast<std::size_t>(i)], row[i]);
            horizon = std::max(horizon, ii_ - 1 + p.ops[static_cast<std::size_t>(i)].latency);
        }
        for (std::size_t f = 0; f < p.write_ports.size(); ++f) {
            const int cap = p.write_ports[f];
            long total = 0;
            for (const ModelOp& o : p.ops) total += o.writes[f];
            const bool full = total == static_cast<long>(cap) * ii_; // every landing row holds cap writes
            for (int a = 0; a < horizon; ++a) {
                BoolVarArgs own, later, old; // this pass's copies landing at a; in a's row later; the last pass's
                IntArgs own_w, later_w, old_w;
                int old_most = 0;
                for (int i = 0; i < n; ++i) {
                    const int w = p.ops[static_cast<std::size_t>(i)].writes[f], lat = p.ops[static_cast<std::size_t>(i)].latency;
                    if (w == 0) continue;
                    for (int q = 0; q < ii_; ++q) {
                        const int land = q + lat;
                        const BoolVar b = at[static_cast<std::size_t>(i)][q];
                        if ((a - land) % ii_ == 0 && a >= land && (copies == 0 || (a - land) / ii_ < copies))
                            own << b, own_w << w;
                        else if ((land - a) % ii_ == 0)
                            later << b, later_w << w;
                        if (land - bubble - a >= ii_ && (land - bubble - a) % ii_ == 0 && (copies == 0 || (land - bubble - a) / ii_ <= copies))
                            old << b, old_w << w, old_most += w;
                    }
                }
                if (own.size() == 0 || old_most == 0) continue;
                IntVar mine(*this, 0, cap), before(*this, 0, old_most);
                linear(*this, own_w, own, IRT_EQ, mine);
                linear(*this, old_w, old, IRT_EQ, before);
                if (full) { // a's landing row is full: what does not land at a now lands there later
                    IntVar rest(*this, 0, cap);
                    linear(*this, later_w, later, IRT_EQ, rest);
                    rel(*this, mine + rest == cap);
                }
                rel(*this, (mine >= 1) >> (mine + before <= cap));
            }
        }
    }
};

// The deadline, and the node budget when there is one (the restart engine hands a stop its
// statistics summed over restarts).
class Budget : public Search::Stop {
  public:
    Budget(std::chrono::steady_clock::time_point deadline, std::uint64_t nodes) : deadline_(deadline), nodes_(nodes) {}
    bool stop(const Search::Statistics& s, const Search::Options&) override {
        return (nodes_ > 0 && s.node >= nodes_) || std::chrono::steady_clock::now() >= deadline_;
    }

  private:
    std::chrono::steady_clock::time_point deadline_;
    std::uint64_t nodes_;
};

} // namespace

ModelProblem machine_problem(const isa::Machine& m) {
    ModelProblem p;
    p.slot_count = static_cast<int>(m.slots.size());
    for (std::size_t f = 0; f < m.regs.size(); ++f)
        p.read_ports[f] = static_cast<int>(m.regs[f].read_ports), p.write_ports[f] = static_cast<int>(m.regs[f].write_ports);
    p.bubble = static_cast<int>(m.branch_penalty);
    return p;
}

ModelOp model_op(const isa::Machine& m, const isa::Instr& in) {
    ModelOp op;
    op.latency = static_cast<int>(m.latency_of(in.info()));
    for (const isa::RegOperand& o : isa::register_operands(in)) {
        const std::size_t f = static_cast<std::size_t>(o.file);
        if (o.write) ++op.writes[f], op.written.emplace_back(static_cast<int>(f), o.reg);
        else ++op.reads[f];
    }
    for (std::size_t s = 0; s < m.slots.size(); ++s)
        if (m.slots[s].accepts(in.info().cls)) op.slots |= 1u << s;
    return op;
}

bool tables_may_exist(const ModelProblem& p, BackEdgeRule rule) {
    TableSpace root(p, rule);
    return root.status() != SS_FAILED;
}

ModelSearch search_tables(const ModelProblem& p, BackEdgeRule rule, std::chrono::steady_clock::time_point deadline,
                          const TableAccept& accept, std::uint64_t node_limit) {
    using Clock = std::chrono::steady_clock;
    ModelSearch out;
    const auto left = [&] { return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count(); };
    if (left() <= 0) {
        out.outcome = ModelSearch::Timeout;
        return out;
    }
    auto root = std::make_unique<TableSpace>(p, rule);
    if (root->status() == SS_FAILED) return out; // Exhausted: the rules alone leave no table
    Budget stop(deadline, node_limit);
    Search::Options o;
    o.threads = 1;
    o.stop = &stop;
    o.cutoff = Search::Cutoff::luby(100); // restarts keep CHB from a bad early choice
    RBS<TableSpace, DFS> engine(root.get(), o);
    root.reset();
    bool accepted = false, late = false;
    while (std::unique_ptr<TableSpace> s{engine.next()}) {
        // Each table is assembled (milliseconds): the clock is read before each.
        if (Clock::now() >= deadline) {
            late = true;
            break;
        }
        std::vector<int> rows, stages;
        for (int i = 0; i < s->row.size(); ++i) rows.push_back(s->row[i].val()), stages.push_back(s->stage[i].min());
        if (accept(rows, stages)) {
            accepted = true;
            break;
        }
    }
    out.nodes = engine.statistics().node;
    out.outcome = accepted ? ModelSearch::Accepted : late || engine.stopped() ? ModelSearch::Timeout : ModelSearch::Exhausted;
    return out;
}

} // namespace nesshi::sched::pipe
