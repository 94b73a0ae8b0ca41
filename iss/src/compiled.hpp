// What compiled runs (iss/compiled.hpp) are made of: the generated code of a straight run keeps
// its cycle and budget in a Counts, calls op<O, Direct>(...) with constant operands and its
// issue cycle (Counts::cycle) for each operation (val<O> for a held result or a latency-1 result
// kept in a local, below), one of end/jump/jump_to/stop/leave for each bundle's end (with clocal,
// land_before, cexit or cflush around held results, end's store_locals and queue_locals (defer)
// around locals, jump_held and Counts::lasts_to), and nothing else of the engine, so that the
// engine can change behind these.
//
// A compiled run is entered at the bundle core.pc and leaves the core exactly as the threaded
// chain (chain.hpp) would: op<> is the handlers' semantics<> (handlers.hpp) with its operands
// known, so isa::kOps[O].eval; end<> is then<kEnd + flags>, jump<> and jump_to<> then<kJump + flags>,
// stop() kExit. It may go further than the chain: on a machine with a branch penalty, where the
// chain stops at every control bundle, it goes on across a control bundle with a constant
// target, and when it takes the branch it adds the bubble as EngineLoop::loop does (jump_to's
// Bubble; c.bubbled, which run_plain counts as cycles, not bundles).
// The run entry/exit contract at the top of chain.hpp holds for them as for the chain: a bundle
// ends as the chain ends it (chain.hpp finish_counts, or jump_to: execution counts by pass; the counts in
// Counts), its ring slot lands as land_ring_at lands it, and a run goes into a FIFO bundle only when
// its fast gate (chain.hpp gate_passes) passes at its issue cycle.
// It returns true when control goes on to another run (core.pc is the next bundle, not issued
// yet: run_compiled enters that run) and false when it stops in bundle core.pc with its ops
// executed, which EngineLoop::run_plain and loop() then finish as after a chain.
#pragma once

#include "chain.hpp"
#include "core.hpp"
#include "handlers.hpp"

#include "isa/ops.hpp"

#include <cstdint>
#include <cstring>
#include <initializer_list>

namespace nesshi::iss::detail {

// run_plain's hook: the compiled runs from core.pc until one stops.
inline void run_compiled(Core& c) {
    while (c.compiled[c.pc](c)) {}
}

// An op's fields as constants of the generated code (handlers.hpp's FromRecord for records).
struct Constants {
    uint16_t dst_, a_, b_, c_;
    uint32_t imm_, latency_, index_, bundle_;
    uint16_t dst() const { return dst_; }
    uint16_t reg(isa::Field f) const { return f == isa::Field::Rs1 ? a_ : f == isa::Field::Rs2 ? b_ : c_; }
    uint32_t imm() const { return imm_; }
    uint32_t latency() const { return latency_; }
    uint32_t index() const { return index_; }
    uint32_t bundle() const { return bundle_; }
    const DecodedOp& record(const Core& c) const { return c.ops[index_]; } // misses, FIFO channels
};

// Row O with its operands given, issued in `cycle` (Counts::cycle): the handlers' semantics, ending as kReturn.
template <size_t O, bool Direct>
[[gnu::always_inline]] inline void op(Core& c, uint64_t cycle, uint16_t dst, uint16_t ra, uint16_t rb, uint16_t rc,
                                      uint32_t imm, uint32_t lat, uint32_t index, uint32_t bundle) {
    semantics<O, Direct, kReturn>(c, Constants{dst, ra, rb, rc, imm, lat, index, bundle}, cycle, 0);
}

// The cycle and the budget inside a run, kept in the generated function's locals rather than
// in c.cycle and c.left. Inside a run both are a function of the bundle's index j as long as
// control goes straight on: the budget left in bundle j is k - j cycles (bundles, and the bubbles
// of branches taken: run_plain takes those out of the bundle budget), its cycle end - (k - j) (end:
// the cycle at which the budget reaches 0), so a bundle's end tests k against its index (or not at
// all, in a head copy's budget-free copy: lasts_to) and
// updates nothing; a goto from bundle j to bundle t adds t - (j + 1) to k. Written back at every
// exit; the cycle also before anything a host provides may read it (semantics<> puts it before
// a channel or a cache model, put_cycle before a gate). Nothing inside a run reads c.left.
struct Counts {
    uint64_t k, end;
    // Scalar loads: the run before stored these one by one (leave), and GCC's vectorizer read
    // them as one 16-byte load, which cannot be forwarded from two stores (a stall on every
    // entry: a fifth of the time in the IC's sphere loop at balls).
    explicit Counts(const Core& c) {
        uint64_t left = c.left;
        asm("" : "+r"(left));
        k = left + c.pc;
        end = c.cycle + left;
    }
    bool spent(uint32_t j) const { return k == j; }
    // No bundle from the current one to j - 1 spends the budget (a run's head copy tests this once
    // and then runs a copy of those bundles without the test, compiled_emit.cpp).
    bool lasts_to(uint32_t j) const { return k >= j; }
    uint64_t cycle(uint32_t j) const { return end - (k - j); }
    void put_cycle(Core& c, uint32_t j) const { c.cycle = cycle(j); }
    void put(Core& c, uint32_t j) const {
        c.cycle = cycle(j);
        c.left = k - j;
    }
    void go(uint32_t j, uint32_t t) { k += uint64_t{t} - (j + 1); } // bundle j finished, t next
    // A branch penalty: p cycles pass with no bundle issued, when the budget has room for them
    // after bundle j (a budget of bundles that has none stops a little early: loop() goes on).
    bool room(uint32_t j, uint32_t p) const { return k - j - 1 >= p; }
    void bubble(uint32_t p) { k -= p; }
};

// The ring writes landing at `cycle`, once bundle j of a run has ended: land_ring (chain.hpp)
// with j's lat1_writes given as constants W0, W1 (its write_adjust credit).
template <uint32_t W0, uint32_t W1> [[gnu::noinline]] void cland_ring(Core& c, uint64_t cycle) {
    land_ring_at(c, cycle, W0, W1);
}
// The same when the ring's slot for the cycle after bundle j holds writes.
template <uint32_t W0, uint32_t W1> [[gnu::always_inline]] inline void cland(Core& c, const Counts& n, uint32_t j) {
    const uint64_t cycle = n.cycle(j + 1);
    if (c.ring[cycle & c.mask].n) cland_ring<W0, W1>(c, cycle);
}

// The run stops in bundle `bundle` (the last bundle of a run that does not jump, kExit, or any
// bundle the chain would stop in), or, bundle `bundle` finished, goes on to the run holding `to`.
[[gnu::always_inline]] inline bool stop(Core& c, const Counts& n, uint32_t bundle) {
    n.put(c, bundle);
    c.pc = bundle;
    return false;
}
[[gnu::always_inline]] inline bool leave(Core& c, const Counts& n, uint32_t bundle, uint32_t to) {
    n.put(c, bundle + 1);
    c.pc = to;
    return true;
}

// The gate of FIFO bundle `to` before a compiled run goes into it from bundle `bundle`: asked at
// to's issue cycle, as step_gated asks it (chain.hpp), out of line.
[[gnu::noinline]] inline bool cgate_at(Core& c, uint32_t to) { return gate_passes(c, c.bundles[to]); }
[[gnu::always_inline]] inline bool cgate(Core& c, const Counts& n, uint32_t bundle, uint32_t to) {
    n.put_cycle(c, bundle + 1);
    return cgate_at(c, to);
}

// The ring slot of `cycle` when the generator knows what it holds: writes to registers R..., in
// the order they were pushed (chain.hpp land_slot with its loop and the file test done at
// compile time).
template <uint32_t W0, uint32_t W1, uint16_t... R> [[gnu::always_inline]] inline void cland_known(Core& c, uint64_t cycle) {
    RingSlot& s = c.ring[cycle & c.mask];
    uint32_t i = 0;
    ((c.r[R] = s.w[i++].value), ...);
    constexpr uint32_t count = sizeof...(R), floats = (0u + ... + ((R >> 7) & 1u));
    c.pending -= count;
    s.n = 0;
    landed_counts(c, cycle, count - floats, floats, W0, W1);
}

// What the end of bundle j does about the ring: probe the next cycle's slot when writes are
// pending (Probe), nothing (NoRing: the generator proved that no write lands then), land the
// slot (Ring: it proved that it holds exactly writes to R...; compiled_emit.cpp has the proof), or
// land R... when the slot holds no more (Expect: it knows those, not what was pushed before the run).
struct Probe {
    template <uint32_t W0, uint32_t W1> [[gnu::always_inline]] static void after(Core& c, const Counts& n, uint32_t j) {
        if (c.pending) [[unlikely]]
            cland<W0, W1>(c, n, j);
    }
};
struct NoRing {
    template <uint32_t W0, uint32_t W1> static void after(Core&, const Counts&, uint32_t) {}
};
template <uint16_t... R> struct Ring {
    template <uint32_t W0, uint32_t W1> [[gnu::always_inline]] static void after(Core& c, const Counts& n, uint32_t j) {
        cland_known<W0, W1, R...>(c, n.cycle(j + 1));
    }
};
// The slot holds writes to R... pushed by the run since its entry, after any pushed before it
// that land then too (the generator cannot rule those out): it holds just R... exactly when its
// count is theirs, else it lands as Probe would.
template <uint16_t... R> struct Expect {
    template <uint32_t W0, uint32_t W1> [[gnu::always_inline]] static void after(Core& c, const Counts& n, uint32_t j) {
        const uint64_t cycle = n.cycle(j + 1);
        if (c.ring[cycle & c.mask].n == sizeof...(R)) [[likely]] {
            if constexpr (sizeof...(R) != 0) cland_known<W0, W1, R...>(c, cycle);
        } else {
            cland_ring<W0, W1>(c, cycle);
        }
    }
};

// Held writes. A compute or load result of a run's head copy (the code entered at its first
// bundle, straight on to its `last` bundle, across branches not taken: compiled_emit.cpp) that
// lands at the end of a bundle of that copy before `last`, in a ring slot that receives only such
// results from the copy, is kept in the run's local v<i> rather than pushed into the ring:
// `v<i> = val<O>(...)` at issue, `c.r[dst] = uint32_t(v<i>)` and clocal at the end that lands it.
// When the run stops before that end (cexit), or a branch taken leaves the copy (cflush), the
// held writes still in flight go into the ring in their issue order, so that the ring holds what
// it would have held. An end in the
// first max_lat - 1 of the copy may find writes pushed before the run in the slot: land_before
// lands those first.
struct Held {
    uint32_t issue, end; // the bundle that computes it, the one whose end lands it
    uint16_t dst;
    uint32_t latency, index;
};

// Row O's result on registers ra, rb, rc and imm, read now (as semantics<> computes it): a
// Compute row's value, or a Load row's, or Core::kLoadFailed when the load faulted (it raised
// the fault; its bundle then stops the run, and nothing is pushed for it).
template <size_t O>
[[gnu::noinline]] uint64_t cload_miss(Core& c, uint64_t cycle, uint32_t index, uint32_t addr) {
    c.cycle = cycle; // a host's cache model may ask its processor's cycle()
    const uint64_t v = c.load_checked(c.ops[index], addr, isa::kOps[O].mem_bytes);
    return v == Core::kLoadFailed ? v : extend<O>(uint32_t(v));
}
template <size_t O>
[[gnu::always_inline]] inline uint64_t val(Core& c, uint64_t cycle, uint16_t ra, uint16_t rb, uint16_t rc, uint32_t imm,
                                           uint32_t index) {
    constexpr const isa::OpInfo& info = isa::kOps[O];
    const Constants f{kNoReg, ra, rb, rc, imm, 0, index, 0};
    const uint32_t v = info.eval(src<O, isa::Field::Rs1>(c, f), src<O, isa::Field::Rs2>(c, f), src<O, isa::Field::Rs3>(c, f), imm);
    if constexpr (info.kind == isa::Kind::Compute) {
        return v;
    } else {
        static_assert(info.kind == isa::Kind::Load);
        if (!c.mem->tlb_hit<info.mem_bytes>(v)) [[unlikely]]
            return cload_miss<O>(c, cycle, index, v);
        uint32_t w = 0;
        std::memcpy(&w, c.mem->tlb_data(v), info.mem_bytes);
        return extend<O>(w);
    }
}
// A result computed by val<O> goes where the op would have put it (Core::push_at), issued in
// cycle `now`; a load that faulted puts nothing.
[[gnu::always_inline]] inline void push_result(Core& c, uint64_t now, uint16_t dst, uint32_t latency, uint32_t index,
                                               uint64_t value) {
    if (value != Core::kLoadFailed) c.push_at(now, dst, latency, index, uint32_t(value));
}
inline void push_held(Core& c, const Counts& n, const Held& h, uint64_t value) {
    push_result(c, n.cycle(h.issue), h.dst, h.latency, h.index, value);
}
// The run leaves the head copy after bundle `bundle`'s ops (a stop, or a branch taken out of
// it): its held writes not landed yet go into the ring. `v`: the values of held[0, v.size()),
// a list built on this path alone (the run's own v<i> are scalars that never escape).
[[gnu::noinline]] inline void cflush(Core& c, Counts n, uint32_t bundle, const Held* held, std::initializer_list<uint64_t> v) {
    for (uint32_t i = 0; i < v.size(); ++i)
        if (held[i].issue <= bundle && held[i].end >= bundle) push_held(c, n, held[i], v.begin()[i]);
}
// The run stopped in bundle `bundle` (end<> returned false, or jump_held held it): cflush.
[[gnu::noinline]] inline bool cexit(Core& c, Counts n, uint32_t bundle, const Held* held, std::initializer_list<uint64_t> v) {
    cflush(c, n, bundle, held, v);
    return false;
}
// The writes pushed before the run that land with held ones at the end of bundle j (the first
// max_lat - 1 ends of the head copy: the run before may have pushed them), landed first, as they
// were pushed first: how many per file.
[[gnu::noinline]] inline Landed cland_before(Core& c, uint64_t cycle) { return land_slot(c, c.ring[cycle & c.mask]); }
[[gnu::always_inline]] inline Landed land_before(Core& c, const Counts& n, uint32_t j) {
    const uint64_t cycle = n.cycle(j + 1);
    if (c.ring[cycle & c.mask].n == 0) [[likely]]
        return {};
    return cland_before(c, cycle);
}
// After the held writes landing at the end of bundle j were stored (NI integer and NF float ones,
// after `before`).
template <uint32_t W0, uint32_t W1, uint32_t NI, uint32_t NF>
[[gnu::always_inline]] inline void clocal(Core& c, const Counts& n, uint32_t j, Landed before = {}) {
    landed_counts(c, n.cycle(j + 1), NI + before.ints, NF + before.floats, W0, W1);
}

// A latency-1 result the generator keeps in a local to its bundle's end rather than queueing it
// in Core::wb_* (Core::push_at): stored at the end (end's store_locals); when the run stops in the
// bundle, queued there as the op would have queued it (`defer`, in op order).
[[gnu::always_inline]] inline void defer(Core& c, uint64_t v, uint16_t dst, uint32_t index) {
    push_result(c, 0, dst, 1, index, v); // latency 1: queued for the bundle's end, whatever `now`
}
struct NoLocals {
    void operator()() const {}
};

// The end of bundle `bundle` inside a run (then<kEnd + flags>): false when the chain stops in it
// (Gate: the next bundle is a FIFO bundle, entered only when its fast gate passes; W0, W1: its
// lat1_writes; Land: what it does about the ring; Budget: test the budget, unless the generator
// knows it lasts (Counts::lasts_to); store_locals, queue_locals: its latency-1 results kept in
// locals, stored before the ring lands as Core::land_direct's were, or queued by `defer`).
template <bool Commit, bool Events, bool Gate, uint32_t W0, uint32_t W1, class Land, bool Budget = true,
          class Stores = NoLocals, class Defer = NoLocals>
[[gnu::always_inline]] inline bool end(Core& c, Counts& n, uint32_t bundle, Stores store_locals = {},
                                      Defer queue_locals = {}) {
    if constexpr (Events)
        if (c.event) [[unlikely]] {
            queue_locals();
            return stop(c, n, bundle);
        }
    if (Budget && n.spent(bundle)) [[unlikely]] {
        queue_locals();
        return stop(c, n, bundle);
    }
    if constexpr (Gate)
        if (!cgate(c, n, bundle, bundle + 1)) [[unlikely]] {
            queue_locals();
            return stop(c, n, bundle);
        }
    finish_counts<Commit, false>(c, bundle, bundle + 1);
    store_locals();
    Land::template after<W0, W1>(c, n, bundle);
    return true;
}

// The end of control bundle `bundle` when the chain goes on across it (then<kJump + flags>):
// the bundle it goes to, or kStopped (the chain stops in it).
inline constexpr uint32_t kStopped = ~uint32_t{0};
template <bool Commit, uint32_t W0, uint32_t W1> [[gnu::always_inline]] inline uint32_t jump(Core& c, Counts& n, uint32_t bundle) {
    const uint32_t ev = c.event;
    if ((ev & ~uint32_t{kTaken}) || n.spent(bundle)) [[unlikely]] {
        stop(c, n, bundle);
        return kStopped;
    }
    const uint32_t to = ev ? c.next_pc : bundle + 1;
    if (to >= c.nb || (c.bundles[to].slow && !cgate(c, n, bundle, to))) [[unlikely]] {
        stop(c, n, bundle);
        return kStopped;
    }
    finish_counts<Commit, true>(c, bundle, to);
    if (c.pending) [[unlikely]]
        cland<W0, W1>(c, n, bundle);
    return to;
}

// The same for a control bundle whose one control op has a constant target: the generator knows
// where it goes when the branch is taken (Taken) and when not, and whether that bundle is a FIFO
// bundle (Gate) inside the program; jump()'s tests of c.next_pc, c.nb and slow fold away. The
// caller has tested the events and the budget (jump_held).
template <bool Budget = true> [[gnu::always_inline]] inline bool jump_held(const Core& c, const Counts& n, uint32_t bundle) {
    return (c.event & ~uint32_t{kTaken}) || (Budget && n.spent(bundle));
}
// Bubble: the machine's branch penalty, the cycles after a taken branch in which no bundle issues
// (EngineLoop::loop's kTaken): counted in c.bubbled, landing the ring as land_slow lands cycles
// that follow no bundle (cbubble); a budget without room for them stops in the branch, and the
// general loop carries the bubble past the limit as it does.
[[gnu::noinline]] inline void cbubble(Core& c, uint64_t from, uint32_t p) {
    for (uint64_t t = from + 1; t <= from + p; ++t) {
        const Landed l = land_slot(c, c.ring[t & c.mask]);
        if (l.ints + l.floats) {
            c.last_ring_cycle = t;
            c.last_ring = {l.ints, l.floats};
        }
        ++c.write_adjust[0][l.ints];
        ++c.write_adjust[1][l.floats];
    }
}
template <bool Commit, bool Taken, bool Gate, uint32_t W0, uint32_t W1, uint32_t Bubble = 0>
[[gnu::always_inline]] inline bool jump_to(Core& c, Counts& n, uint32_t bundle, uint32_t to) {
    constexpr uint32_t bubble = Taken ? Bubble : 0;
    if constexpr (bubble != 0)
        if (!n.room(bundle, bubble)) [[unlikely]]
            return stop(c, n, bundle);
    if constexpr (Gate) {
        Counts after = n; // `to` issues after the bubble
        after.bubble(bubble);
        if (!cgate(c, after, bundle, to)) [[unlikely]]
            return stop(c, n, bundle);
    }
    if constexpr (Commit) c.land_direct();
    ++c.leave[bundle + 1];
    ++c.enter[to];
    if constexpr (Taken) {
        ++c.taken[bundle];
        c.event = 0;
    }
    c.jump_from = bundle;
    c.jump_to = to;
    c.jump_bubbled = bubble != 0;
    if (c.pending) [[unlikely]]
        cland<W0, W1>(c, n, bundle);
    if constexpr (bubble != 0) {
        const uint64_t from = n.cycle(bundle + 1);
        n.bubble(bubble);
        c.bubbled += bubble;
        if (c.pending) [[unlikely]] {
            cbubble(c, from, bubble);
        } else {
            c.write_adjust[0][0] += bubble;
            c.write_adjust[1][0] += bubble;
        }
    }
    return true;
}

} // namespace nesshi::iss::detail
