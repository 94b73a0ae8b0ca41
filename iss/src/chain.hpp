// Threaded code: what a fast-engine handler does after its operation (its Tail).
//
// Inside a straight run every op record holds a handler that ends in a tail call of the next
// record's handler, and the last op of each bundle also does the end of the bundle, so a run
// is one chain of jumps with no dispatch loop. The chain leaves the core exactly as the
// general loop's turn per bundle would (see EngineLoop::run_plain): it stops with the
// stopping bundle's ops executed and nothing else, and the loop finishes that bundle.
//
// GCC 12 has no musttail: every call here is in tail position with the handler's own
// signature, and no handler may keep an addressable local, so -O2 emits jumps
// (tests/iss/threaded_test.cpp runs a long run on a small stack to check it).
#pragma once

#include "core.hpp"

#include <cstdint>

namespace nesshi::iss::detail {

// Tails: Return (the dispatch loop's handlers), Next (an op that is not its bundle's last),
// Exit (last op of a run's last bundle), End + flags (last op of any other bundle of a run),
// Jump + flags (last op of a control bundle without halt when the branch penalty is 0: the
// chain goes on at the next bundle or the branch's target, when no FIFO gate guards it).
inline constexpr int kReturn = 0, kNext = 1, kExit = 2, kEnd = 3, kJump = 7;
inline constexpr int kEndCommit = 1, kEndEvents = 2; // flags added to kEnd and kJump
inline constexpr int kNumTails = kJump + 4;

// The ring writes landing in this cycle, inside a run (the bundle before is owed its histogram
// credit); land_ring_then: then the next bundle's first op. Out of line and reached by tail
// calls, so that the handlers need no stack frame, and land_then's test of an empty slot needs
// none either.
[[gnu::always_inline]] inline void land_ring(Core& c, uint32_t prev_bundle) {
    RingSlot& s = c.ring[c.cycle & c.mask];
    const uint32_t count = s.n;
    uint32_t ring_float = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const RingWrite w = s.w[i];
        c.r[w.reg] = w.value;
        ring_float += (w.reg >> 7) & 1;
    }
    c.pending -= count;
    s.n = 0;
    const uint32_t ring[2] = {count - ring_float, ring_float};
    c.last_ring_cycle = c.cycle;
    c.last_ring = {ring[0], ring[1]};
    const auto& prev = c.bundles[prev_bundle].lat1_writes;
    for (int f = 0; f < 2; ++f) {
        if (!ring[f]) continue;
        --c.write_adjust[f][prev[f]];
        ++c.write_adjust[f][prev[f] + ring[f]];
    }
}
[[gnu::noinline]] inline void land_ring_then(Core& c, const DecodedOp& next, uint32_t prev_bundle) {
    land_ring(c, prev_bundle);
    return next.tfn(c, next);
}

// The end of a bundle inside a run with ring writes pending: most cycles land none of them.
[[gnu::noinline]] inline void land_then(Core& c, const DecodedOp& next, uint32_t prev_bundle) {
    if (c.ring[c.cycle & c.mask].n) return land_ring_then(c, next, prev_bundle);
    return next.tfn(c, next);
}

template <int T> [[gnu::always_inline]] inline void then(Core& c, const DecodedOp& d) {
    if constexpr (T == kReturn) {
        return;
    } else if constexpr (T == kNext) {
        const DecodedOp& n = (&d)[1];
        return n.tfn(c, n);
    } else if constexpr (T == kExit) {
        c.pc = d.bundle;
    } else if constexpr (T >= kJump) {
        constexpr bool commit = (T - kJump) & kEndCommit;
        const uint32_t ev = c.event;
        if ((ev & ~uint32_t{kTaken}) || c.left == 0) [[unlikely]] { // loop() handles them (and the limits)
            c.pc = d.bundle;
            return;
        }
        const uint32_t to = ev ? c.next_pc : d.bundle + 1;
        if (to >= c.nb || c.bundles[to].slow) [[unlikely]] { // a bad pc, or a FIFO gate: loop() again
            c.pc = d.bundle;
            return;
        }
        if constexpr (commit) c.land_direct();
        ++c.exec[d.bundle];
        if (ev) {
            ++c.taken[d.bundle];
            c.event = 0;
        }
        c.jump_from = d.bundle; // the bundle before `to`, should the chain stop there
        c.jump_to = to;
        ++c.cycle;
        --c.left;
        const DecodedOp& n = c.ops[c.bundles[to].first];
        if (c.pending) [[unlikely]]
            return land_then(c, n, d.bundle);
        return n.tfn(c, n);
    } else {
        constexpr bool commit = (T - kEnd) & kEndCommit; // the bundle queues latency-1 writes
        constexpr bool events = (T - kEnd) & kEndEvents; // it has a load or store (fault, stall)
        if constexpr (events) {
            if (c.event) [[unlikely]] {
                c.pc = d.bundle;
                return;
            }
        }
        if (c.left == 0) [[unlikely]] { // the budget, the cycle limit or the chain's cap
            c.pc = d.bundle;
            return;
        }
        if constexpr (commit) c.land_direct();
        ++c.exec[d.bundle];
        ++c.cycle;
        --c.left;
        const DecodedOp& n = (&d)[1]; // ops are stored in bundle order: the next bundle's first
        if (c.pending) [[unlikely]]
            return land_then(c, n, d.bundle);
        return n.tfn(c, n);
    }
}

} // namespace nesshi::iss::detail
