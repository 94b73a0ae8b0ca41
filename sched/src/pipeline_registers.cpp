#include "pipeline_registers.hpp"

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
#include <cstdint>
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

// First fit of each virtual's copies, in `order`, on registers whose cycles on the circle (the
// kernel, unroll x II cycles) are free; `take` gives a new register. The cycles are bit sets of
// 64-cycle words (the allocator tries every register for every copy).
template <class Take>
void share(Allocation& a, const Region& r, const Schedule& s, int circle, const std::vector<std::size_t>& order, Take& take) {
    using Cycles = std::vector<std::uint64_t>;
    const std::size_t words = (static_cast<std::size_t>(circle) + 63) / 64;
    std::vector<Cycles> busy[2];  // per file, per register taken: cycles occupied (empty: a register of its own)
    std::vector<int> busy_reg[2]; // the register of each
    a.regs.assign(r.virtuals.size(), {});
    Cycles need(words);
    for (const std::size_t v : order) {
        const Virtual& x = r.virtuals[v];
        const int f = static_cast<int>(x.file);
        const bool own = r.carry.count(x.name) || r.liveout.count(x.name);
        const int t0 = s.time[static_cast<std::size_t>(x.def)];
        for (int c = 0; c < a.copies[v]; ++c) {
            std::fill(need.begin(), need.end(), 0);
            for (int k = c; k < a.unroll; k += a.copies[v])
                for (int t = 0; t < a.lifetime[v]; ++t) {
                    const auto at = static_cast<std::size_t>(((t0 + k * s.ii + t) % circle + circle) % circle);
                    need[at / 64] |= std::uint64_t{1} << (at % 64);
                }
            int slot = -1;
            for (std::size_t b = 0; !own && slot < 0 && b < busy[f].size(); ++b) {
                const Cycles& held = busy[f][b];
                if (held.empty()) continue; // a register of its own
                bool free = true;
                for (std::size_t w = 0; free && w < words; ++w) free = (need[w] & held[w]) == 0;
                if (free) slot = static_cast<int>(b);
            }
            if (slot < 0) {
                busy_reg[f].push_back(take(x.file, x.name));
                busy[f].push_back(own ? Cycles{} : Cycles(words, 0));
                slot = static_cast<int>(busy[f].size()) - 1;
            }
            if (!own) {
                Cycles& held = busy[f][static_cast<std::size_t>(slot)];
                for (std::size_t w = 0; w < words; ++w) held[w] |= need[w];
            }
            a.regs[v].push_back(reg_name(x.file, busy_reg[f][static_cast<std::size_t>(slot)]));
        }
    }
}

} // namespace

Allocation allocate(const Region& r, const Graph& g, const Schedule& s, const std::set<std::pair<int, int>>& named,
                    const isa::Machine& m, std::string_view file, int min_unroll) {
    Allocation a;
    std::vector<int> pool[2];
    for (int f = 0; f < 2; ++f)
        for (int reg = 0; reg < static_cast<int>(m.regs[static_cast<std::size_t>(f)].count); ++reg)
            if (!named.count({f, reg})) pool[f].push_back(reg); // taken from the top down
    auto take = [&](isa::RegFile f, const std::string& what) {
        auto& p = pool[static_cast<int>(f)];
        if (p.empty())
            throw RegisterPressure(base::SourceLoc(file, static_cast<int>(r.begin + 1)),
                 fmt::format("register pressure: no free {} register left for {} ({} has {} per file, the source names "
                             "{}, the tool has taken the other {} for the kernel's register copies)",
                             isa::kRegFileNames[static_cast<std::size_t>(f)], what, m.name,
                             m.regs[static_cast<std::size_t>(f)].count,
                             std::count_if(named.begin(), named.end(), [&](auto& x) { return x.first == static_cast<int>(f); }),
                             std::count_if(a.scratch.begin(), a.scratch.end(),
                                           [&](const std::string& x) { return x[0] == file_prefix(f); })));
        const int reg = p.back();
        p.pop_back();
        a.scratch.push_back(reg_name(f, reg));
        return reg;
    };
    if (!r.is_while) a.counter = take(isa::RegFile::Int, "the kernel counter");
    // Lifetimes: from the def's issue to the last read (a new value may be issued in the cycle of
    // the last read of the old one, the exposed pipeline's rule).
    int need = 1;
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int def = r.virtuals[v].def;
        int last = s.time[static_cast<std::size_t>(def)] + g.nodes[static_cast<std::size_t>(def)].latency;
        for (const Edge& e : g.ddg.edges)
            if (e.from == def && e.why.rfind("true ", 0) == 0 && e.why.substr(5) == r.virtuals[v].name)
                last = std::max(last, s.time[static_cast<std::size_t>(e.to)] + e.distance * s.ii);
        if (r.is_while) { // a value the exit path reads must outlive the exit test that may hand it out
            const std::string& name = r.virtuals[v].name;
            const auto c = r.carry.find(name);
            const bool now = r.liveout.count(name) || (c != r.carry.end() && def < r.exit_op);
            const bool next = c != r.carry.end() && (def > r.exit_op || !c->second.old.empty());
            const int tb = s.time[static_cast<std::size_t>(r.exit_op)];
            if (now) last = std::max(last, tb + 1);
            if (next) last = std::max(last, tb + s.ii + 1);
        }
        const int life = last - s.time[static_cast<std::size_t>(def)];
        a.lifetime.push_back(life);
        const int k = std::max(1, (life + s.ii - 1) / s.ii);
        a.copies.push_back(static_cast<int>(std::bit_ceil(static_cast<unsigned>(k))));
        need = std::max(need, a.copies.back());
    }
    a.unroll = std::max(need, min_unroll);
    // A while loop pays the taken-branch bubble once per kernel pass: more kernel copies (the same
    // registers rotating, a power of two) until it is at most a twentieth of the pass. No remainder
    // to run and no register more; only more code and exit paths.
    if (r.is_while) a.unroll *= bubble_repeats(static_cast<int>(m.branch_penalty), s.ii * a.unroll, kMaxBubbleUnroll / a.unroll);
    // First a register set of its own for every virtual, while there are enough. Else virtuals
    // share registers where their lifetimes do not meet. In the kernel (unroll x II cycles, a
    // circle) copy c of v holds the instances of the iterations k = c mod copies, each from its
    // def's issue to its last read (the next owner may issue in that cycle); the prologue,
    // epilogue and exit paths hold subsets of those instances. Carried values and live-outs keep
    // registers of their own: the value before the loop and after its exit live longer than any
    // instance in the kernel. Shared first fit in program order; when that runs out of registers,
    // by the cycle each value starts on the circle, then by lifetime per copy, longest first (each
    // packs some circles tighter). The error, when all fail, names the value the last could not place.
    const int circle = a.unroll * s.ii;
    std::vector<std::size_t> by_program(r.virtuals.size());
    std::iota(by_program.begin(), by_program.end(), std::size_t{0});
    std::vector<std::size_t> by_start = by_program, by_lifetime = by_program;
    auto start = [&](std::size_t v) { return ((s.time[static_cast<std::size_t>(r.virtuals[v].def)] % circle) + circle) % circle; };
    std::stable_sort(by_start.begin(), by_start.end(), [&](std::size_t x, std::size_t y) { return start(x) < start(y); });
    std::stable_sort(by_lifetime.begin(), by_lifetime.end(),
                     [&](std::size_t x, std::size_t y) { return a.lifetime[x] * a.copies[y] > a.lifetime[y] * a.copies[x]; });
    auto own_sets = [&] {
        a.regs.clear();
        for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
            std::vector<std::string> regs;
            for (int c = 0; c < a.copies[v]; ++c)
                regs.push_back(reg_name(r.virtuals[v].file, take(r.virtuals[v].file, r.virtuals[v].name)));
            a.regs.push_back(regs);
        }
    };
    auto shared = [&](const std::vector<std::size_t>& order) { return [&, o = &order] { share(a, r, s, circle, *o, take); }; };
    const std::function<void()> attempts[] = {own_sets, shared(by_program), shared(by_start), shared(by_lifetime)};
    const std::vector<int> pool0[2] = {pool[0], pool[1]};
    const std::vector<std::string> scratch0 = a.scratch;
    for (std::size_t k = 0;; ++k) {
        try {
            attempts[k]();
            return a;
        } catch (const RegisterPressure&) {
            if (k + 1 == std::size(attempts)) throw;
            pool[0] = pool0[0], pool[1] = pool0[1];
            a.scratch = scratch0;
        }
    }
}

int most_repeats(int pass) {
    int most = 1;
    while (most < kMaxGroups && 2 * most * pass <= kMaxKernelBundles) most *= 2;
    return most;
}

int bubble_repeats(int penalty, int pass, int most) {
    int f = 1;
    while (f < most && 20 * penalty > pass * f) f *= 2;
    return f;
}

bool kernel_landings_ok(const Graph& g, const Schedule& s, int unroll, int groups, const isa::Machine& m, bool entry_nops) {
    if (m.branch_penalty == 0) return true;
    const int copies = unroll * groups, pass = copies * s.ii, bubble = static_cast<int>(m.branch_penalty);
    int last_stage = 0, longest = 1;
    for (int t : s.time) last_stage = std::max(last_stage, t / s.ii);
    for (const Node& nd : g.nodes) longest = std::max(longest, nd.latency);
    longest = std::max(longest, static_cast<int>(m.latency_of(s.counter.info())));
    // Per cycle of a pass (and beyond its end): writes issued in it, writes in flight into it.
    using Count = std::array<std::uint32_t, isa::kNumRegFiles>;
    std::vector<Count> own(static_cast<std::size_t>(pass + longest)), in(own.size());
    auto add = [](Count& c, const isa::Instr& x) {
        for (const isa::RegOperand& o : isa::register_operands(x))
            if (o.write) ++c[static_cast<std::size_t>(o.file)];
    };
    auto issue = [&](const isa::Instr& x, int at, bool in_prologue) {
        const int lands = at + static_cast<int>(m.latency_of(x.info()));
        add(own[static_cast<std::size_t>(lands)], x);
        if (lands < pass) return;
        if (lands - pass - bubble >= 0) add(in[static_cast<std::size_t>(lands - pass - bubble)], x); // around the back edge
        if (in_prologue && !entry_nops) add(in[static_cast<std::size_t>(lands - pass)], x);      // from the prologue
    };
    for (int c = 0; c < copies; ++c) {
        for (std::size_t i = 0; i < g.nodes.size(); ++i)
            issue(g.nodes[i].instr, c * s.ii + s.time[i] % s.ii, s.time[i] / s.ii < last_stage);
        if (s.loop_control) issue(s.counter, c * s.ii + s.counter_row, false); // each copy counts its iteration
    }
    for (std::size_t y = 0; y < own.size(); ++y)
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            const std::size_t k = static_cast<std::size_t>(f);
            if (own[y][k] > 0 && own[y][k] + in[y][k] > m.regs[k].write_ports) return false;
        }
    return true;
}

} // namespace nesshi::sched::pipe
