#include "pipeline_search.hpp"

#include "assembler/assembler.hpp"
#include "base/error.hpp"
#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <span>
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

namespace {

// An op as the port checks count it: the cycles to its landing and its writes per register file
// (computed once per op: the checks run for every candidate cycle of every op).
struct Writes {
    int latency = 1;
    std::array<int, isa::kNumRegFiles> per_file{};
};

Writes writes_of(const isa::Machine& m, const isa::Instr& in) {
    Writes w;
    w.latency = static_cast<int>(m.latency_of(in.info()));
    for (int f = 0; f < isa::kNumRegFiles; ++f) w.per_file[static_cast<std::size_t>(f)] = writes_to(in, f);
    return w;
}

// A row of a modulo reservation table: its ops, with their nodes (-1 for loop control) and writes.
struct Row {
    std::vector<isa::Instr> ops;
    std::vector<int> nodes;
    std::vector<Writes> writes;
    void push(const isa::Instr& in, int node, const Writes& w) {
        ops.push_back(in);
        nodes.push_back(node);
        writes.push_back(w);
    }
    void erase(std::size_t k) {
        ops.erase(ops.begin() + static_cast<std::ptrdiff_t>(k));
        nodes.erase(nodes.begin() + static_cast<std::ptrdiff_t>(k));
        writes.erase(writes.begin() + static_cast<std::ptrdiff_t>(k));
    }
    void pop() {
        ops.pop_back();
        nodes.pop_back();
        writes.pop_back();
    }
};

// Around the kernel's back edge a taken-branch bubble of b cycles delays the next pass, so the
// writes still in flight from the last pass land b cycles earlier against the new pass's than
// modulo II: a write landing at row + latency (from the pass start) meets, at cycle T, this
// pass's writes landing at T (T >= land, T - land a multiple of II) and the last pass's at
// land - b - T a positive multiple of II. Checked at the cycles `in` (at `row`) lands in either
// way, against the ops of `rows`; with few kernel copies some of these instances do not exist
// (conservative).
bool back_edge_ok(const isa::Machine& m, int ii, const std::vector<Row>& rows, const Writes& in, int row) {
    const int b = static_cast<int>(m.branch_penalty);
    if (b == 0) return true;
    const int land_in = row + in.latency;
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        const int w_in = in.per_file[static_cast<std::size_t>(f)];
        if (w_in == 0) continue;
        thread_local std::vector<std::pair<int, int>> lands; // (land, writes) of every writer of f; asked per place tried
        lands.assign(1, {land_in, w_in});
        int last = land_in;
        for (int r = 0; r < ii; ++r)
            for (const Writes& other : rows[static_cast<std::size_t>(r)].writes)
                if (const int w = other.per_file[static_cast<std::size_t>(f)]; w > 0) {
                    lands.push_back({r + other.latency, w});
                    last = std::max(last, lands.back().first);
                }
        auto meet_ok = [&](int at) {
            int own = 0, old = 0;
            for (const auto& [land, w] : lands) {
                if (at >= land && (at - land) % ii == 0) own += w;
                else if (land - b - at >= ii && (land - b - at) % ii == 0) old += w;
            }
            return own == 0 || static_cast<std::uint32_t>(own + old) <= m.regs[static_cast<std::size_t>(f)].write_ports;
        };
        for (int at = land_in; at < last; at += ii)
            if (!meet_ok(at)) return false;
        for (int at = land_in - b - ii; at >= 0; at -= ii)
            if (!meet_ok(at)) return false;
    }
    return true;
}

// Whether a row's ops and `extra` make a legal bundle. Asked for every place the search tries: no
// allocation (the slots are assigned on a copy on the stack). More ops than slots never fit.
bool bundle_legal(const isa::Machine& m, std::span<const isa::Instr> row, const isa::Instr& extra) {
    const std::size_t n = row.size() + 1;
    if (n > m.slots.size() || n > static_cast<std::size_t>(isa::kMaxSlots)) return false;
    std::array<isa::Instr, isa::kMaxSlots> ops;
    std::copy(row.begin(), row.end(), ops.begin());
    ops[row.size()] = extra;
    std::array<int, isa::kMaxSlots> pinned;
    pinned.fill(-1);
    const std::span<isa::Instr> bundle(ops.data(), n);
    if (!isa::assign_slots(m, bundle, std::span<const int>(pinned).first(n))) return false;
    return isa::bundle_fits(m, bundle);
}

// The reservation table: its rows, and the writes landing in each cycle mod II per register file
// (kept as ops come and go: the port check asks for every candidate cycle of every op).
class Table {
  public:
    void reset(int ii) {
        ii_ = ii;
        rows_.assign(static_cast<std::size_t>(ii), {});
        lands_.assign(static_cast<std::size_t>(ii), {});
    }
    const std::vector<Row>& rows() const { return rows_; }
    const Row& operator[](int row) const { return rows_[static_cast<std::size_t>(row)]; }
    void push(int row, const isa::Instr& in, int node, const Writes& w) {
        rows_[static_cast<std::size_t>(row)].push(in, node, w);
        count(row, w, 1);
    }
    void erase(int row, std::size_t k) {
        Row& r = rows_[static_cast<std::size_t>(row)];
        count(row, r.writes[k], -1);
        r.erase(k);
    }
    void pop(int row) {
        Row& r = rows_[static_cast<std::size_t>(row)];
        count(row, r.writes.back(), -1);
        r.pop();
    }
    // Whether the writes landing in `in`'s cycle (mod II), per register file, stay within the
    // ports with `in` placed at `row`.
    bool landings_ok(const isa::Machine& m, const Writes& in, int row) const {
        const auto& at = lands_[static_cast<std::size_t>((row + in.latency) % ii_)];
        for (std::size_t f = 0; f < at.size(); ++f)
            if (in.per_file[f] > 0 && static_cast<std::uint32_t>(in.per_file[f] + at[f]) > m.regs[f].write_ports) return false;
        return true;
    }

  private:
    void count(int row, const Writes& w, int sign) {
        auto& at = lands_[static_cast<std::size_t>((row + w.latency) % ii_)];
        for (std::size_t f = 0; f < at.size(); ++f) at[f] += sign * w.per_file[f];
    }
    int ii_ = 1;
    std::vector<Row> rows_;
    std::vector<std::array<int, isa::kNumRegFiles>> lands_;
};

class ModuloScheduler {
  public:
    // attempt 0 orders ops by height alone; later attempts break ties (and near-ties) at random.
    // `stages` > 0: only schedules of at most that many stages (every op issues before cycle
    // stages * II, and early enough for the longest path after it to end there too).
    ModuloScheduler(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter,
                    int attempt = 0, int exit_node = -1, int stages = 0)
        : g_(g), m_(m), ii_(ii), branch_(branch), counter_(counter), attempt_(attempt), exit_(exit_node),
          limit_(stages > 0 ? stages * ii - 1 : -1) {
        for (const Node& nd : g_.nodes) writes_.push_back(writes_of(m_, nd.instr));
    }

    std::optional<Schedule> run() {
        const int n = static_cast<int>(g_.nodes.size());
        rows_.reset(ii_);
        // Loop control first: the branch ends the kernel; the counter decrement anywhere. A while
        // loop has neither: its exit test is pinned to the last row (fits).
        int counter_row = -1;
        if (exit_ < 0) {
            if (!place_fixed(branch_, ii_ - 1)) return std::nullopt;
            for (int row = 0; row < ii_ && counter_row < 0; ++row)
                if (place_fixed(counter_, row)) counter_row = row;
            if (counter_row < 0) return std::nullopt;
        }
        heights();
        latest_.assign(static_cast<std::size_t>(n), std::numeric_limits<int>::max());
        if (limit_ >= 0)
            for (int i = 0; i < n; ++i) { // the longest path after an op must end by the limit too
                latest_[static_cast<std::size_t>(i)] = limit_ - std::max(0, height_[static_cast<std::size_t>(i)]);
                if (latest_[static_cast<std::size_t>(i)] < 0) return std::nullopt;
            }
        if (attempt_ >= kAttemptsPerII) { // critical ops first: the least slack, then the greatest height
            const std::vector<int> slack = slacks();
            std::mt19937 rng(static_cast<unsigned>(attempt_));
            for (std::size_t i = 0; i < height_.size(); ++i)
                height_[i] = (100000 - slack[i]) * 4096 + height_[i] * 4 + (attempt_ > kAttemptsPerII ? static_cast<int>(rng() % 6) : 0);
        } else if (attempt_ > 0) { // perturb: a random order among ops of similar height
            std::mt19937 rng(static_cast<unsigned>(attempt_));
            for (int& h : height_) h = h * 4 + static_cast<int>(rng() % 6);
        }
        time_.assign(static_cast<std::size_t>(n), -1);
        last_time_.assign(static_cast<std::size_t>(n), -1);
        // Under a stage limit a shorter search: as many stages are found as with the full budget
        // (bench_sched's while loops), at a third of the time when none exists.
        int budget = std::max(200, n * (limit_ >= 0 ? 10 : 40));
        while (budget-- > 0) {
            int op = -1;
            for (int i = 0; i < n; ++i)
                if (time_[static_cast<std::size_t>(i)] < 0 &&
                    (op < 0 || height_[static_cast<std::size_t>(i)] > height_[static_cast<std::size_t>(op)]))
                    op = i;
            if (op < 0) break;
            int estart = 0;
            for (const Edge& e : g_.ddg.edges)
                if (e.to == op && time_[static_cast<std::size_t>(e.from)] >= 0 && e.from != op)
                    estart = std::max(estart, time_[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii_);
            const int latest = latest_[static_cast<std::size_t>(op)];
            if (estart > latest) return std::nullopt;
            int chosen = -1;
            for (int t = estart; t < estart + ii_ && t <= latest && chosen < 0; ++t)
                if (fits(op, t)) chosen = t;
            if (chosen < 0) { // displace: take the first cycle it has not had yet, evict what conflicts
                auto own_row = [&](int t) { return op == exit_ ? t + ((ii_ - 1 - t) % ii_ + ii_) % ii_ : t; }; // not earlier
                const int prev = last_time_[static_cast<std::size_t>(op)];
                chosen = own_row(prev < estart ? estart : prev + 1);
                if (chosen > latest) chosen = own_row(estart); // past the stage limit: from the earliest again
                if (chosen > latest) return std::nullopt;
                evict_for(op, chosen);
                if (!fits(op, chosen)) return std::nullopt;
            }
            place(op, chosen);
            for (const Edge& e : g_.ddg.edges) // successors now too early
                if (e.from == op && e.to != op && time_[static_cast<std::size_t>(e.to)] >= 0 &&
                    chosen + e.latency - e.distance * ii_ > time_[static_cast<std::size_t>(e.to)])
                    unplace(e.to);
        }
        for (int i = 0; i < n; ++i)
            if (time_[static_cast<std::size_t>(i)] < 0) return std::nullopt;
        for (const Edge& e : g_.ddg.edges) // self edges and the final state
            if (time_[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii_ > time_[static_cast<std::size_t>(e.to)])
                return std::nullopt;
        Schedule s;
        s.ii = ii_;
        s.time = time_;
        s.normalise();
        s.branch = branch_;
        s.counter = counter_;
        s.counter_row = counter_row;
        s.loop_control = exit_ < 0;
        return s;
    }

    // Whether `s` keeps every rule `run` places ops under: its loop control, then each op in
    // issue order where `fits` allows it, then every edge.
    bool admits(const Schedule& s) {
        const int n = static_cast<int>(g_.nodes.size());
        rows_.reset(ii_);
        time_.assign(static_cast<std::size_t>(n), -1);
        last_time_ = time_;
        if (s.loop_control && (!place_fixed(branch_, ii_ - 1) || !place_fixed(counter_, s.counter_row))) return false;
        std::vector<int> order(static_cast<std::size_t>(n));
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            return s.time[static_cast<std::size_t>(a)] < s.time[static_cast<std::size_t>(b)];
        });
        for (int op : order) {
            if (!fits(op, s.time[static_cast<std::size_t>(op)])) return false;
            place(op, s.time[static_cast<std::size_t>(op)]);
        }
        for (const Edge& e : g_.ddg.edges)
            if (s.time[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii_ > s.time[static_cast<std::size_t>(e.to)])
                return false;
        return true;
    }

  private:
    bool legal(int row, const isa::Instr& in) const { return bundle_legal(m_, rows_[row].ops, in); }

    // Writes landing in each cycle (mod II) per register file, across rows, within the ports, and
    // around the back edge.
    bool landings_ok(const Writes& w, int row) const {
        return rows_.landings_ok(m_, w, row) && back_edge_ok(m_, ii_, rows_.rows(), w, row);
    }

    bool induction_ok(int op, int t) const {
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        for (const Induction& ind : g_.inductions) {
            const int lat = g_.nodes[static_cast<std::size_t>(ind.op)].latency;
            if (lat <= 1) continue;
            const bool reads = nd.adjusted && nd.base == ind.reg;
            if (op == ind.op) { // its own step: no adjusted read may fall inside its flight
                for (int i = 0; i < static_cast<int>(g_.nodes.size()); ++i) {
                    const Node& o = g_.nodes[static_cast<std::size_t>(i)];
                    if (!(o.adjusted && o.base == ind.reg) || time_[static_cast<std::size_t>(i)] < 0) continue;
                    const int d = ((time_[static_cast<std::size_t>(i)] - t) % ii_ + ii_) % ii_;
                    if (d > 0 && d < lat) return false;
                }
                if (lat > ii_) return false;
            } else if (reads && time_[static_cast<std::size_t>(ind.op)] >= 0) {
                const int d = ((t - time_[static_cast<std::size_t>(ind.op)]) % ii_ + ii_) % ii_;
                if (d > 0 && d < lat) return false;
            }
        }
        return true;
    }

    bool fits(int op, int t) const {
        const int row = ((t % ii_) + ii_) % ii_;
        if (op == exit_ && row != ii_ - 1) return false;
        const isa::Instr& in = g_.nodes[static_cast<std::size_t>(op)].instr;
        return legal(row, in) && landings_ok(writes_[static_cast<std::size_t>(op)], row) && induction_ok(op, t);
    }

    bool place_fixed(const isa::Instr& in, int row) {
        const Writes w = writes_of(m_, in);
        if (!legal(row, in) || !landings_ok(w, row)) return false;
        rows_.push(row, in, -1, w);
        return true;
    }

    void place(int op, int t) {
        const int row = ((t % ii_) + ii_) % ii_;
        rows_.push(row, g_.nodes[static_cast<std::size_t>(op)].instr, op, writes_[static_cast<std::size_t>(op)]);
        time_[static_cast<std::size_t>(op)] = t;
        last_time_[static_cast<std::size_t>(op)] = t;
    }

    void unplace(int op) {
        const int t = time_[static_cast<std::size_t>(op)];
        if (t < 0) return;
        const int row = ((t % ii_) + ii_) % ii_;
        const Row& r = rows_[row];
        for (std::size_t k = 0; k < r.nodes.size(); ++k)
            if (r.nodes[k] == op) {
                rows_.erase(row, k);
                break;
            }
        time_[static_cast<std::size_t>(op)] = -1;
    }

    // Evicts what keeps `op` from t: ops of its row (most recently placed first) while the bundle
    // is illegal, then ops whose writes land in its landing cycle on a file it writes, then any.
    void evict_for(int op, int t) {
        const int row = ((t % ii_) + ii_) % ii_;
        const isa::Instr& in = g_.nodes[static_cast<std::size_t>(op)].instr;
        const int land = (row + static_cast<int>(m_.latency_of(in.info()))) % ii_;
        auto writes = [](const isa::Instr& x, int f) {
            for (const isa::RegOperand& o : isa::register_operands(x))
                if (o.write && static_cast<int>(o.file) == f) return true;
            return false;
        };
        for (int guard = 0; guard < 64 && !fits(op, t); ++guard) {
            int victim = -1;
            const Row& r = rows_[row];
            if (!legal(row, in)) {
                for (std::size_t k = r.nodes.size(); k-- > 0;)
                    if (r.nodes[k] >= 0) {
                        victim = r.nodes[k];
                        break;
                    }
            } else if (!landings_ok(writes_[static_cast<std::size_t>(op)], row)) {
                for (int i = 0; i < static_cast<int>(g_.nodes.size()) && victim < 0; ++i) {
                    const int ti = time_[static_cast<std::size_t>(i)];
                    if (ti < 0 || i == op) continue;
                    const isa::Instr& x = g_.nodes[static_cast<std::size_t>(i)].instr;
                    if ((((ti % ii_) + ii_) % ii_ + static_cast<int>(m_.latency_of(x.info()))) % ii_ != land) continue;
                    for (int f = 0; f < isa::kNumRegFiles && victim < 0; ++f)
                        if (writes(in, f) && writes(x, f)) victim = i;
                }
            }
            if (victim < 0) // the row holds only loop control, or the landing is taken by it: evict any
                for (int i = 0; i < static_cast<int>(g_.nodes.size()) && victim < 0; ++i)
                    if (time_[static_cast<std::size_t>(i)] >= 0 && i != op) victim = i;
            if (victim < 0) return;
            unplace(victim);
        }
    }

    // Each op's slack: the critical path (issue to issue) less the longest paths into it and out
    // of it, at this II; 0 on a critical path.
    std::vector<int> slacks() const {
        const std::vector<int> depth = g_.ddg.longest_paths(ii_, false);
        int cp = 0;
        for (std::size_t i = 0; i < depth.size(); ++i) cp = std::max(cp, depth[i] + height_[i]);
        std::vector<int> slack(depth.size());
        for (std::size_t i = 0; i < depth.size(); ++i) slack[i] = cp - depth[i] - height_[i];
        return slack;
    }

    void heights() { height_ = g_.ddg.longest_paths(ii_, true); }

    const Graph& g_;
    const isa::Machine& m_;
    int ii_;
    isa::Instr branch_, counter_;
    int attempt_ = 0;
    int exit_ = -1; // a while loop's exit test: only in the last row
    int limit_ = -1; // the last cycle an op may issue in (a stage limit), or none
    std::vector<Writes> writes_; // per node
    Table rows_;
    std::vector<int> time_, last_time_, height_, latest_;
};

} // namespace

// The registers of file `f` op x writes.
int writes_to(const isa::Instr& x, int f) {
    int c = 0;
    for (const isa::RegOperand& o : isa::register_operands(x))
        if (o.write && static_cast<int>(o.file) == f) ++c;
    return c;
}

std::optional<Schedule> modulo_schedule(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch,
                                        const isa::Instr& counter, int attempt, int exit_node, int stages) {
    return ModuloScheduler(g, m, ii, branch, counter, attempt, exit_node, stages).run();
}

bool table_admits(const Graph& g, const isa::Machine& m, const Schedule& s, int exit_node) {
    return ModuloScheduler(g, m, s.ii, s.branch, s.counter, 0, exit_node).admits(s);
}

} // namespace nesshi::sched::pipe
