// Threaded code: what a fast-engine handler does after its operation (its Tail).
//
// Inside a straight run every op record holds a handler that ends in a tail call of the next
// record's handler, and the last op of each bundle also does the end of the bundle, so a run
// is one chain of jumps with no dispatch loop. The chain leaves the core exactly as the
// general loop's turn per bundle would (see EngineLoop::run_plain): it stops with the
// stopping bundle's ops executed and nothing else, and the loop finishes that bundle.
//
// The run entry/exit contract (for anything else entered from EngineLoop::run_plain, such as
// compiled runs): run_plain enters at bundle c.pc, whose FIFO gate (if any) loop() has passed,
// with c.left = bundles that may be finished after the one it stops in, c.jump_to = ~0, and one
// pass begun at c.pc (++c.enter[c.pc]). A bundle is finished by: landing its queued latency-1
// writes (land_direct), for a taken jump ++c.taken and c.event = 0, ++c.cycle, --c.left, then
// at the next cycle the ring slot's writes (land_then: registers, c.pending, last_ring and the
// write_adjust credit of the bundle before). Execution counts are by pass: falling through counts
// nothing, a jump from b to t does ++c.leave[b + 1], ++c.enter[t] and sets jump_from/jump_to.
// A taken jump on a machine with a branch penalty (compiled runs only) then passes the bubble's
// cycles: c.left and the cycle move by them, c.bubbled counts them (run_plain takes them out of
// the bundle budget and into bubble_cycles), their ring slots land as cycles that follow no
// bundle, and jump_bubbled says so (the cycle a stop in t landed last was a bubble's).
// Entering a FIFO bundle needs its fast gate (step_gated: asked at its issue cycle). The stop:
// c.pc = the bundle whose ops have run but which is not finished (its events in c.event,
// next_pc set by a taken control op); run_plain then ends the pass (++c.leave[c.pc]) and
// settles land_next/lat1_owed/last_owed, and loop() finishes that bundle as any other.
//
// GCC 12 has no musttail: every call here is in tail position, its first arguments the
// handler's own (the chain's state stays in the registers it came in; out-of-line helpers add
// theirs after), and no handler may keep an addressable local, so -O2 emits jumps
// (tests/iss/threaded_test.cpp runs a long run on a small stack to check it).
#pragma once

#include "core.hpp"

#include <cstdint>

namespace nesshi::iss::detail {

// Tails: Return (the dispatch loop's handlers), Next (an op that is not its bundle's last),
// Exit (last op of a run's last bundle), End + flags (last op of any other bundle of a run),
// Jump + commit flag (last op of a control bundle without halt when the branch penalty is 0:
// the chain goes on at the next bundle or the branch's target).
//
// FIFO bundles: the chain goes into one (End + kEndGate, or a Jump whose target is one) only
// when its fast gate passes (gate_passes); otherwise it stops in the bundle before, exactly as
// at any other stop, and the general loop's fifo_gate decides at the FIFO bundle (wait, block,
// deadlock, no channel) as it would have without the chain.
inline constexpr int kReturn = 0, kNext = 1, kExit = 2, kEnd = 3, kJump = 11;
inline constexpr int kEndCommit = 1, kEndEvents = 2, kEndGate = 4; // flags added to kEnd (kJump: commit only)
inline constexpr int kNumTails = kJump + 2;

// The hot state of a chain: the current cycle and c.left travel as the handlers' last two
// arguments (ThreadedHandler), so that a bundle's end neither loads nor stores them; the Core's
// copies are stale inside a chain and written at a stop (stop_at) and before anything that
// reads them (a channel call or a cache model's access: a host's may read its processor's cycle()).
[[gnu::always_inline]] inline void stop_at(Core& c, uint32_t bundle, uint64_t cycle, uint64_t left) {
    c.pc = bundle;
    c.cycle = cycle;
    c.left = left;
}

// The ring writes landing in cycle `cycle`, inside a run (the bundle before is owed its
// histogram credit); land_ring_then: then the next bundle's first op. Out of line and reached by
// tail calls, so that the handlers need no stack frame, and land_then's test of an empty slot
// needs none either. The chain's state stays in the registers it came in (the extras go last).
// landed_counts: what follows the stores once ring_int and ring_float writes landed in cycle
// `cycle`; w0, w1: the bundle before's lat1_writes. Compiled runs call it with constants when the
// generator knows the slot (compiled.hpp cland_known) or lands the run's own values (clocal).
[[gnu::always_inline]] inline void landed_counts(Core& c, uint64_t cycle, uint32_t ring_int, uint32_t ring_float,
                                                 uint32_t w0, uint32_t w1) {
    c.last_ring_cycle = cycle;
    c.last_ring = {ring_int, ring_float};
    // The credit moves per file by hand: a loop over a local pair kept the pair on the stack.
    if (ring_int) {
        uint64_t* adjust = c.write_adjust[0];
        --adjust[w0];
        ++adjust[w0 + ring_int];
    }
    if (ring_float) {
        uint64_t* adjust = c.write_adjust[1];
        --adjust[w1];
        ++adjust[w1 + ring_float];
    }
}
// land_slot: the writes of slot s land in their registers, in push order, and leave the ring;
// how many per file (the rest of the bookkeeping is the caller's: landed_counts, or a bubble's).
struct Landed {
    uint32_t ints = 0, floats = 0;
};
[[gnu::always_inline]] inline Landed land_slot(Core& c, RingSlot& s) {
    const uint32_t count = s.n;
    uint32_t floats = 0;
    for (const RingWrite *w = s.w.data(), *e = w + count; w != e; ++w) { // no copy: GCC kept one on the stack
        c.r[w->reg] = w->value;
        floats += (w->reg >> 7) & 1;
    }
    c.pending -= count;
    s.n = 0;
    return {count - floats, floats};
}
[[gnu::always_inline]] inline void land_ring_at(Core& c, uint64_t cycle, uint32_t w0, uint32_t w1) {
    const Landed l = land_slot(c, c.ring[cycle & c.mask]);
    landed_counts(c, cycle, l.ints, l.floats, w0, w1);
}
[[gnu::always_inline]] inline void land_ring_at(Core& c, uint32_t prev_bundle, uint64_t cycle) {
    const auto& prev = c.bundles[prev_bundle].lat1_writes;
    land_ring_at(c, cycle, prev[0], prev[1]);
}
[[gnu::noinline]] inline void land_ring_then(Core& c, const ThreadedOp& next, uint64_t cycle, uint64_t left,
                                             const ThreadedOp& prev) {
    land_ring_at(c, prev.bundle, cycle);
    return next.fn(c, next, cycle, left);
}

// The end of a bundle inside a run with ring writes pending: most cycles land none of them.
// `prev`: the last op of the bundle before, whose bundle is read only when writes land (so the
// bundle's end need not load it).
[[gnu::noinline]] inline void land_then(Core& c, const ThreadedOp& next, uint64_t cycle, uint64_t left,
                                        const ThreadedOp& prev) {
    if (c.ring[cycle & c.mask].n) return land_ring_then(c, next, cycle, left, prev);
    return next.fn(c, next, cycle, left);
}

// The end of bundle `bundle` once the chain goes on to bundle `to`: what the general loop's
// turn does after the handlers (commit, counts), short of the cycle and the budget (the chain's
// registers, or a compiled run's Counts) and of landing the next cycle's ring writes. A bundle's
// execution is counted by pass (Processor::flush_passes): nothing to count when the chain falls
// through; a jump ends a pass after `bundle` and begins one at `to`.
template <bool Commit, bool Jump> [[gnu::always_inline]] inline void finish_counts(Core& c, uint32_t bundle, uint32_t to) {
    if constexpr (Commit) c.land_direct();
    if constexpr (Jump) {
        ++c.leave[bundle + 1];
        ++c.enter[to];
        if (c.event) { // kTaken, the only event a chain goes on with
            ++c.taken[bundle];
            c.event = 0;
        }
        c.jump_from = bundle; // the bundle before `to`, should the chain stop there
        c.jump_to = to;
    }
}

// finish_counts, the next cycle and budget in the chain's registers, then the ring writes landing
// now and `to`'s first op.
template <bool Commit, bool Jump>
[[gnu::always_inline]] inline void step(Core& c, const ThreadedOp& d, uint32_t to, uint64_t cycle, uint64_t left) {
    finish_counts<Commit, Jump>(c, d.bundle, to);
    const ThreadedOp& n = Jump ? c.tops[c.bundles[to].first] : (&d)[1]; // ops are in bundle order
    if (c.pending) [[unlikely]]
        return land_then(c, n, cycle + 1, left - 1, d);
    return n.fn(c, n, cycle + 1, left - 1);
}

// A FIFO bundle's fast gate at the current cycle: for each channel and direction it uses (in
// the order of their first op), a channel is attached and holds `need` readable words or has
// room for `need`. It passes exactly when the general gate (EngineLoop::fifo_gate) would say
// Go, which asks the same of each op with the words up to it (Channel::readable's contract),
// and it asks nothing the general gate would not ask first when it does not pass.
inline bool gate_passes(const Core& c, const DecodedBundle& b) {
    for (const FifoNeed *g = c.needs + b.gate_first, *e = g + b.gate_count; g != e; ++g) {
        const Channel* ch = c.channels[g->slot];
        if (!ch) return false;
        if (g->recv ? ch->readable(c.cycle, g->need) < g->need : ch->writable() < g->need) return false;
    }
    return true;
}

// The end of a bundle whose successor `to` is a FIFO bundle. Out of line (the gate calls the
// channels) and reached by a tail call. When the gate does not pass, the chain stops here.
template <bool Commit, bool Jump>
[[gnu::noinline]] void step_gated(Core& c, const ThreadedOp& d, uint64_t cycle, uint64_t left, uint32_t to) {
    c.cycle = cycle + 1; // asked at to's issue cycle, the one the general gate sees (for the channels)
    if (!gate_passes(c, c.bundles[to])) [[unlikely]]
        return stop_at(c, d.bundle, cycle, left);
    return step<Commit, Jump>(c, d, to, cycle, left);
}

// R: DecodedOp for kReturn (the dispatch loop's handlers, compiled runs), ThreadedOp otherwise.
template <int T, class R>
[[gnu::always_inline]] inline void then(Core& c, const R& d, [[maybe_unused]] uint64_t cycle,
                                        [[maybe_unused]] uint64_t left) {
    if constexpr (T == kReturn) {
        return;
    } else if constexpr (T == kNext) {
        const ThreadedOp& n = (&d)[1];
        return n.fn(c, n, cycle, left);
    } else if constexpr (T == kExit) {
        return stop_at(c, d.bundle, cycle, left);
    } else if constexpr (T >= kJump) {
        constexpr bool commit = (T - kJump) & kEndCommit;
        const uint32_t ev = c.event;
        if ((ev & ~uint32_t{kTaken}) || left == 0) [[unlikely]] // loop() handles them (and the limits)
            return stop_at(c, d.bundle, cycle, left);
        const uint32_t to = ev ? c.next_pc : d.bundle + 1;
        if (to >= c.nb) [[unlikely]] // a bad pc: loop() again
            return stop_at(c, d.bundle, cycle, left);
        if (c.bundles[to].slow) return step_gated<commit, true>(c, d, cycle, left, to);
        return step<commit, true>(c, d, to, cycle, left);
    } else {
        constexpr bool commit = (T - kEnd) & kEndCommit; // the bundle queues latency-1 writes
        constexpr bool events = (T - kEnd) & kEndEvents; // it has a load or store (fault, stall)
        constexpr bool gate = (T - kEnd) & kEndGate;     // the next bundle is a FIFO bundle
        if constexpr (events)
            if (c.event) [[unlikely]]
                return stop_at(c, d.bundle, cycle, left);
        if (left == 0) [[unlikely]] // the budget, the cycle limit or the chain's cap
            return stop_at(c, d.bundle, cycle, left);
        if constexpr (gate) return step_gated<commit, false>(c, d, cycle, left, d.bundle + 1);
        else return step<commit, false>(c, d, d.bundle + 1, cycle, left);
    }
}

} // namespace nesshi::iss::detail
