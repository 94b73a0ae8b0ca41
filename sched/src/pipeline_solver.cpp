#include "pipeline_solver.hpp"

#include "isa/ops.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <z3++.h>

#include <algorithm>
#include <array>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace nesshi::sched::pipe {

int iteration_length(const Graph& g, const Schedule& s) {
    const int first = *std::min_element(s.time.begin(), s.time.end());
    int end = 0;
    for (std::size_t i = 0; i < s.time.size(); ++i) end = std::max(end, s.time[i] + g.nodes[i].latency - first);
    return end;
}

namespace {

// The most (op, issue cycle) pairs an encoding may have at the first bound it tries. The IC's
// loops need about 2,000 for a triangle on ic-real and 5,000-8,000 for the quadrics. With z3's
// plain core, 6,500 brings ic-real's two-sided sphere from 39.83 to 38.20 cycles and 5 more of 20
// random IC machines within 1.15x of their run bounds; 9,000 also the cylinder (43.48 -> 41.77)
// but no more random machines, at half as much time again for the random-machine test.
constexpr std::int64_t kMaxIssueCells = 6500;

int mod(int a, int b) { return ((a % b) + b) % b; }

// The resource units (z3's deterministic measure of work) the last check used.
std::uint64_t rlimit_used(const z3::solver& s) {
    const z3::stats st = s.statistics();
    for (unsigned k = 0; k < st.size(); ++k)
        if (st.key(k) == "rlimit count") return st.is_uint(k) ? st.uint_value(k) : static_cast<std::uint64_t>(st.double_value(k));
    return 0;
}

// What an op uses of a bundle, as isa::check_bundle counts it: reads per file at issue, writes
// per file at its landing, and the kinds of slot (slots with the same accept set) that take it.
struct Use {
    std::array<int, isa::kNumRegFiles> reads{}, writes{};
    int latency = 1;
    std::vector<int> kinds;
};

// Longest paths within one iteration (edges of distance 0): each op's earliest issue from the
// ops of no predecessor, and its tail, the cycles from its issue to the end of the iteration
// (its own latency at least). The longest of earliest + tail bounds every schedule's length.
struct Paths {
    std::vector<int> earliest, tail;
    int length = 0;
};

Paths paths_of(const Graph& g, const isa::Machine& m) {
    const std::size_t n = g.nodes.size();
    Paths p;
    p.earliest.assign(n, 0);
    for (const Node& nd : g.nodes) p.tail.push_back(static_cast<int>(m.latency_of(nd.instr.info())));
    for (std::size_t round = 0; round <= n; ++round) {
        bool changed = false;
        for (const Edge& e : g.ddg.edges) {
            if (e.distance != 0 || e.from == e.to) continue;
            const auto f = static_cast<std::size_t>(e.from), t = static_cast<std::size_t>(e.to);
            if (p.earliest[f] + e.latency > p.earliest[t]) p.earliest[t] = p.earliest[f] + e.latency, changed = true;
            if (e.latency + p.tail[t] > p.tail[f]) p.tail[f] = e.latency + p.tail[t], changed = true;
        }
        if (!changed) break;
    }
    for (std::size_t k = 0; k < n; ++k) p.length = std::max(p.length, p.earliest[k] + p.tail[k]);
    return p;
}

// The encoding. Op i issues at T_i in [lo_i, hi_i], in order encoding: ge[i][t - lo_i] is
// "T_i >= t" (t = lo_i + 1 .. hi_i); at[i][t - lo_i] is "T_i == t"; row[i][r] is "T_i mod II ==
// r"; on[i][k][r] "in row r on a slot of kind k" for ops more than one kind of slot takes. A
// dependence T_b >= T_a + d is a binary clause per cycle: ge_a(t) -> ge_b(t + d).
class Encoding {
  public:
    Encoding(z3::context& c, const Graph& g, const isa::Machine& m, const Schedule& found, int exit_node, const Paths& paths,
             int horizon)
        : c_(c), g_(g), m_(m), ii_(found.ii), n_(static_cast<int>(g.nodes.size())),
          // z3's plain SMT core, without the default solver's preprocessing tactics: on these
          // Boolean and pseudo-Boolean encodings it reaches the same schedules (the IC's loops on
          // ic-real) at about two thirds of the time, and a check costs no fixed 6 ms.
          s_(c, z3::solver::simple()) {
        slot_kinds();
        for (const Node& nd : g_.nodes) uses_.push_back(use_of(nd.instr));
        windows(paths, horizon);
        if (!feasible_) return;
        variables();
        dependences();
        resources(found);
        if (exit_node >= 0) s_.add(row_[static_cast<std::size_t>(exit_node)][static_cast<std::size_t>(ii_ - 1)]);
        inductions();
        distinct_writes();
        back_edge();
    }

    bool feasible() const { return feasible_; }
    z3::solver& solver() { return s_; }

    std::vector<int> times(const z3::model& md) const {
        std::vector<int> t(static_cast<std::size_t>(n_));
        for (int i = 0; i < n_; ++i) {
            t[static_cast<std::size_t>(i)] = lo_[static_cast<std::size_t>(i)];
            for (int x = lo_[static_cast<std::size_t>(i)] + 1; x <= hi_[static_cast<std::size_t>(i)]; ++x)
                if (md.eval(ge(i, x), true).is_true()) t[static_cast<std::size_t>(i)] = x;
        }
        return t;
    }

  private:
    void slot_kinds() {
        std::map<std::uint32_t, int> index;
        for (const isa::SlotDesc& s : m_.slots) {
            auto [it, added] = index.emplace(s.classes, static_cast<int>(kind_classes_.size()));
            if (added) {
                kind_classes_.push_back(s.classes);
                kind_count_.push_back(0);
            }
            ++kind_count_[static_cast<std::size_t>(it->second)];
        }
    }

    Use use_of(const isa::Instr& in) const {
        Use u;
        u.latency = static_cast<int>(m_.latency_of(in.info()));
        for (const isa::RegOperand& o : isa::register_operands(in))
            ++(o.write ? u.writes : u.reads)[static_cast<std::size_t>(o.file)];
        const std::uint32_t bit = 1u << static_cast<int>(in.info().cls);
        for (std::size_t k = 0; k < kind_classes_.size(); ++k)
            if (kind_classes_[k] & bit) u.kinds.push_back(static_cast<int>(k));
        return u;
    }

    // Each op's window: from its earliest issue to the horizon less the longest path out of it.
    void windows(const Paths& p, int horizon) {
        lo_ = p.earliest;
        hi_.resize(static_cast<std::size_t>(n_));
        for (std::size_t k = 0; k < hi_.size(); ++k) {
            hi_[k] = horizon - p.tail[k];
            if (hi_[k] < lo_[k] || uses_[k].kinds.empty()) feasible_ = false;
        }
    }

    z3::expr ge(int i, int t) const {
        return ge_[static_cast<std::size_t>(i)][static_cast<std::size_t>(t - lo_[static_cast<std::size_t>(i)] - 1)];
    }

    void variables() {
        ge_.resize(static_cast<std::size_t>(n_));
        row_.resize(static_cast<std::size_t>(n_));
        on_.resize(static_cast<std::size_t>(n_));
        for (int i = 0; i < n_; ++i) {
            const auto k = static_cast<std::size_t>(i);
            const std::string name = "o" + std::to_string(i);
            for (int t = lo_[k] + 1; t <= hi_[k]; ++t) {
                ge_[k].push_back(c_.bool_const((name + "ge" + std::to_string(t)).c_str()));
                if (t > lo_[k] + 1) s_.add(z3::implies(ge_[k].back(), ge_[k][ge_[k].size() - 2]));
            }
            std::vector<z3::expr_vector> in_row; // each its own (a copied expr_vector shares its elements)
            for (int r = 0; r < ii_; ++r) in_row.emplace_back(c_);
            for (int t = lo_[k]; t <= hi_[k]; ++t) { // T_i == t
                z3::expr at = c_.bool_val(true);
                if (t > lo_[k]) at = ge(i, t);
                if (t < hi_[k]) at = at && !ge(i, t + 1);
                in_row[static_cast<std::size_t>(mod(t, ii_))].push_back(at);
            }
            for (int r = 0; r < ii_; ++r) {
                z3::expr rv = c_.bool_const((name + "r" + std::to_string(r)).c_str());
                const z3::expr_vector& ats = in_row[static_cast<std::size_t>(r)];
                s_.add(rv == (ats.empty() ? c_.bool_val(false) : z3::mk_or(ats)));
                row_[k].push_back(rv);
            }
            const std::vector<int>& kinds = uses_[k].kinds;
            if (kinds.size() > 1) { // the kind of slot it takes, in each row
                z3::expr_vector which(c_);
                for (int kind : kinds) which.push_back(c_.bool_const((name + "k" + std::to_string(kind)).c_str()));
                s_.add(z3::atmost(which, 1));
                s_.add(z3::mk_or(which));
                for (std::size_t q = 0; q < kinds.size(); ++q) {
                    std::vector<z3::expr> per_row;
                    for (int r = 0; r < ii_; ++r) per_row.push_back(row_[k][static_cast<std::size_t>(r)] && which[static_cast<unsigned>(q)]);
                    on_[k].push_back(per_row);
                }
            }
        }
    }

    void dependences() {
        for (const Edge& e : g_.ddg.edges) {
            if (e.from == e.to) continue; // the heuristic's schedule keeps these (latency <= distance x II)
            const int d = e.latency - e.distance * ii_;
            const auto a = static_cast<std::size_t>(e.from), b = static_cast<std::size_t>(e.to);
            // T_a >= t implies T_b >= t + d, for every t where the implication says something.
            for (int t = lo_[a]; t <= hi_[a]; ++t) {
                const int need = t + d;
                if (need <= lo_[b]) continue;
                const z3::expr from = t == lo_[a] ? c_.bool_val(true) : ge(e.from, t);
                if (need > hi_[b]) s_.add(!from);
                else s_.add(z3::implies(from, ge(e.to, need)));
            }
        }
    }

    // Per row: slots of each kind, read ports; per landing row: write ports. Loop control (a
    // counted loop's branch and counter) sits in its rows already.
    void resources(const Schedule& found) {
        std::vector<std::pair<Use, int>> fixed;
        if (found.loop_control) {
            fixed.push_back({use_of(found.branch), ii_ - 1});
            fixed.push_back({use_of(found.counter), found.counter_row});
        }
        for (int r = 0; r < ii_; ++r) {
            for (std::size_t kind = 0; kind < kind_classes_.size(); ++kind) {
                z3::expr_vector in(c_);
                int cap = kind_count_[kind];
                for (const auto& [u, fr] : fixed)
                    if (fr == r && u.kinds.size() == 1 && u.kinds[0] == static_cast<int>(kind)) --cap;
                for (int i = 0; i < n_; ++i) {
                    const Use& u = uses_[static_cast<std::size_t>(i)];
                    if (u.kinds.size() == 1) {
                        if (u.kinds[0] == static_cast<int>(kind)) in.push_back(row_[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)]);
                    } else
                        for (std::size_t q = 0; q < u.kinds.size(); ++q)
                            if (u.kinds[q] == static_cast<int>(kind))
                                in.push_back(on_[static_cast<std::size_t>(i)][q][static_cast<std::size_t>(r)]);
                }
                limit(in, {}, cap);
            }
            for (int f = 0; f < isa::kNumRegFiles; ++f) {
                const auto fi = static_cast<std::size_t>(f);
                z3::expr_vector reads(c_), lands(c_);
                std::vector<int> rc, lc;
                int read_cap = static_cast<int>(m_.regs[fi].read_ports), write_cap = static_cast<int>(m_.regs[fi].write_ports);
                for (const auto& [u, fr] : fixed) {
                    if (fr == r) read_cap -= u.reads[fi];
                    if (mod(fr + u.latency, ii_) == r) write_cap -= u.writes[fi];
                }
                for (int i = 0; i < n_; ++i) {
                    const Use& u = uses_[static_cast<std::size_t>(i)];
                    if (u.reads[fi] > 0) reads.push_back(row_[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)]), rc.push_back(u.reads[fi]);
                    if (u.writes[fi] > 0) // lands in row r when issued in row r - latency
                        lands.push_back(row_[static_cast<std::size_t>(i)][static_cast<std::size_t>(mod(r - u.latency, ii_))]), lc.push_back(u.writes[fi]);
                }
                limit(reads, rc, read_cap);
                limit(lands, lc, write_cap);
            }
        }
    }

    // Around the kernel's back edge (a taken-branch bubble of b cycles) the rule of
    // back_edge_ok in pipeline_search.cpp: at each cycle A of a pass where some write of this
    // pass lands (issued in row r, landing at r + latency = A - k x II, k >= 0), those writes and
    // the last passes' landing at A (r + latency - b - A a positive multiple of II) share the
    // file's write ports.
    void back_edge() {
        const int b = static_cast<int>(m_.branch_penalty);
        if (b == 0) return;
        int max_land = 0;
        for (const Use& u : uses_) max_land = std::max(max_land, ii_ - 1 + u.latency);
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            const auto fi = static_cast<std::size_t>(f);
            const int cap = static_cast<int>(m_.regs[fi].write_ports);
            for (int a = 0; a < max_land; ++a) {
                z3::expr_vector own(c_), all(c_);
                std::vector<int> weights;
                int old_total = 0;
                for (int i = 0; i < n_; ++i) {
                    const Use& u = uses_[static_cast<std::size_t>(i)];
                    const int w = u.writes[fi];
                    if (w == 0) continue;
                    const std::vector<z3::expr>& rows = row_[static_cast<std::size_t>(i)];
                    if (const int r = mod(a - u.latency, ii_); r <= a - u.latency) { // lands at a in this pass's frame
                        own.push_back(rows[static_cast<std::size_t>(r)]);
                        all.push_back(rows[static_cast<std::size_t>(r)]);
                        weights.push_back(w);
                    }
                    if (const int r = mod(a + b - u.latency, ii_); r + u.latency - b - a >= ii_) { // a last pass's
                        all.push_back(rows[static_cast<std::size_t>(r)]);
                        weights.push_back(w);
                        old_total += w;
                    }
                }
                if (own.empty() || old_total == 0) continue;
                // own + old <= cap unless no own write lands at a: + old_total x any_own <= cap + old_total
                z3::expr any = c_.bool_const(("land" + std::to_string(f) + "_" + std::to_string(a)).c_str());
                s_.add(any == z3::mk_or(own));
                all.push_back(any);
                weights.push_back(old_total);
                // with `any` false the sum is own + old <= cap + old_total, which own <= cap (the
                // modulo landing limit) already implies
                s_.add(z3::pble(all, weights.data(), cap + old_total));
            }
        }
    }

    // A bundle writes one register once per landing cycle (isa::check_bundle): ops writing the
    // same register (the pipeliner's stand-ins for its virtual registers repeat) with the same
    // latency take different rows.
    // The groups in order of their first op, so that regions differing only in their registers
    // get the same constraints in the same order (and so the same schedule: search_key).
    void distinct_writes() {
        std::map<std::tuple<int, int, int>, std::size_t> group; // (file, register, latency) -> index in writers
        std::vector<std::vector<int>> writers;
        for (int i = 0; i < n_; ++i)
            for (const isa::RegOperand& o : isa::register_operands(g_.nodes[static_cast<std::size_t>(i)].instr))
                if (o.write) {
                    const auto [at, added] = group.emplace(
                        std::tuple{static_cast<int>(o.file), static_cast<int>(o.reg), uses_[static_cast<std::size_t>(i)].latency},
                        writers.size());
                    if (added) writers.emplace_back();
                    writers[at->second].push_back(i);
                }
        for (const std::vector<int>& ops : writers) {
            if (ops.size() < 2) continue;
            for (int r = 0; r < ii_; ++r) {
                z3::expr_vector in(c_);
                for (int i : ops) in.push_back(row_[static_cast<std::size_t>(i)][static_cast<std::size_t>(r)]);
                s_.add(z3::atmost(in, 1));
            }
        }
    }

    // A register file's step in flight (latency > 1) is not read, offset-adjusted, inside it.
    void inductions() {
        for (const Induction& ind : g_.inductions) {
            const int lat = uses_[static_cast<std::size_t>(ind.op)].latency;
            if (lat <= 1) continue;
            for (int o = 0; o < n_; ++o) {
                const Node& nd = g_.nodes[static_cast<std::size_t>(o)];
                if (o == ind.op || !(nd.adjusted && nd.base == ind.reg)) continue;
                for (int r = 0; r < ii_; ++r)
                    for (int d = 1; d < lat; ++d)
                        s_.add(!row_[static_cast<std::size_t>(ind.op)][static_cast<std::size_t>(r)] ||
                               !row_[static_cast<std::size_t>(o)][static_cast<std::size_t>(mod(r + d, ii_))]);
            }
        }
    }

    void limit(const z3::expr_vector& xs, const std::vector<int>& weights, int cap) {
        if (xs.empty()) return;
        if (cap < 0) {
            feasible_ = false;
            return;
        }
        int total = 0;
        for (std::size_t k = 0; k < xs.size(); ++k) total += weights.empty() ? 1 : weights[k];
        if (total <= cap) return;
        if (weights.empty()) s_.add(z3::atmost(xs, static_cast<unsigned>(cap)));
        else s_.add(z3::pble(xs, weights.data(), cap));
    }

    z3::context& c_;
    const Graph& g_;
    const isa::Machine& m_;
    int ii_, n_;
    z3::solver s_;
    bool feasible_ = true;
    std::vector<std::uint32_t> kind_classes_;
    std::vector<int> kind_count_;
    std::vector<Use> uses_;
    std::vector<int> lo_, hi_;
    std::vector<std::vector<z3::expr>> ge_, row_;
    std::vector<std::vector<std::vector<z3::expr>>> on_;
};

} // namespace

IterationBounds iteration_bounds(const Graph& g, const isa::Machine& m) {
    const Paths p = paths_of(g, m);
    return {p.length, *std::max_element(p.earliest.begin(), p.earliest.end())};
}

namespace {

// What the encoding reads of a search, with registers numbered by first use: two regions that
// differ only in their registers (the kernels' loops for two shape codes: `bne %code, r54` against
// r55) are the same search, so it runs once per process (the solver is deterministic; a thread
// asking while another runs it waits for that answer).
std::string search_key(const Graph& g, const isa::Machine& m, const Schedule& found, int exit_node, std::uint64_t budget) {
    std::map<std::pair<int, int>, int> number;
    auto reg = [&](int file, int r) { return number.emplace(std::pair{file, r}, static_cast<int>(number.size())).first->second; };
    std::string key = fmt::format("{:x} {} {} {} {} {}\n", m.fingerprint(), found.ii, exit_node, budget, found.loop_control,
                                  found.counter_row);
    auto instr = [&](const isa::Instr& in) {
        key += in.info().mnemonic;
        for (const isa::RegOperand& o : isa::register_operands(in))
            key += fmt::format(" {}{}{}{}", static_cast<int>(o.file), o.write ? "w" : "r", o.base ? "b" : "", reg(static_cast<int>(o.file), o.reg));
    };
    for (const Node& nd : g.nodes) {
        instr(nd.instr);
        key += fmt::format(" {} {} {} {} {} {} {}\n", nd.latency, nd.mem, nd.store, nd.speculative, nd.width, nd.adjusted,
                           nd.base < 0 ? -1 : reg(static_cast<int>(isa::RegFile::Int), nd.base));
    }
    if (found.loop_control) {
        instr(found.branch);
        instr(found.counter);
    }
    for (const Edge& e : g.ddg.edges) key += fmt::format("\n{} {} {} {}", e.from, e.to, e.latency, e.distance);
    for (const Induction& i : g.inductions) key += fmt::format("\ni {} {}", i.op, reg(static_cast<int>(isa::RegFile::Int), i.reg));
    key += fmt::format("\n{}", fmt::join(found.time, " "));
    return key;
}

using Found = std::optional<std::vector<int>>; // the times found, if any
std::mutex searches_mutex;
std::map<std::string, std::shared_future<Found>>& searches() { // key -> its answer, once there
    static std::map<std::string, std::shared_future<Found>> done;
    return done;
}

// The bisection itself.
std::optional<Schedule> search(const Graph& g, const isa::Machine& m, const Schedule& found, int exit_node, std::uint64_t budget) {
    std::optional<Schedule> out;
    const Paths paths = paths_of(g, m);
    // Bisection between the longest path and the best so far, each bound its own encoding (the
    // windows as narrow as it allows): a satisfied bound moves the best to the schedule's own
    // length, an unsatisfiable one (or one out of budget) the floor.
    int lo = paths.length, hi = iteration_length(g, found) - 1;
    // The encoding grows with each op's window: a long iteration of many ops (slow machines)
    // would spend more building it than the solver's budget buys. Such a region keeps `found`.
    std::int64_t cells = 0;
    for (std::size_t i = 0; i < g.nodes.size(); ++i) cells += std::max(0, lo + (hi - lo) / 2 - paths.tail[i] - paths.earliest[i] + 1);
    if (cells > kMaxIssueCells || budget < 2) return out; // (z3 reads a limit of 0 as none)
    std::uint64_t left = budget;
    try {
        while (lo <= hi && left > 0) {
            const int h = lo + (hi - lo) / 2;
            z3::context c;
            Encoding enc(c, g, m, found, exit_node, paths, h);
            z3::check_result r = z3::unsat;
            if (enc.feasible()) {
                z3::params p(c);
                p.set("rlimit", static_cast<unsigned>(std::min<std::uint64_t>({left, budget / 2, 4000000000u})));
                p.set("random_seed", 0u);
                enc.solver().set(p);
                r = enc.solver().check();
                left -= std::min(left, rlimit_used(enc.solver()));
            }
            if (r != z3::sat) {
                lo = h + 1;
                continue;
            }
            Schedule s = found;
            s.time = enc.times(enc.solver().get_model());
            s.normalise();
            if (!table_admits(g, m, s, exit_node)) break; // the encoding and the table disagree: keep what we have
            hi = iteration_length(g, s) - 1;
            out = std::move(s);
        }
    } catch (const z3::exception&) {
        // the solver improves on a schedule already found: without it, that one stands
    }
    return out;
}

} // namespace

std::optional<Schedule> shortest_schedule(const Graph& g, const isa::Machine& m, const Schedule& found, int exit_node,
                                          std::uint64_t budget) {
    const std::string key = search_key(g, m, found, exit_node, budget);
    std::promise<Found> mine;
    std::shared_future<Found> answer;
    bool run = false;
    {
        std::lock_guard lock(searches_mutex);
        const auto [it, fresh] = searches().emplace(key, std::shared_future<Found>());
        if (fresh) it->second = mine.get_future().share();
        answer = it->second;
        run = fresh;
    }
    if (run) {
        try {
            std::optional<Schedule> out = search(g, m, found, exit_node, budget);
            mine.set_value(out ? Found(out->time) : std::nullopt);
            return out;
        } catch (...) { // not an answer: a later ask runs it again
            {
                std::lock_guard lock(searches_mutex);
                searches().erase(key);
            }
            mine.set_exception(std::current_exception());
            throw;
        }
    }
    const Found& known = answer.get();
    if (!known) return std::nullopt;
    Schedule s = found;
    s.time = *known;
    if (table_admits(g, m, s, exit_node)) return s;
    return std::nullopt;
}


} // namespace nesshi::sched::pipe
