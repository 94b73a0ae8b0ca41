// The turn rule that makes a PE's FIFO traffic independent of how the host interleaves its
// stages. A stage (0 OS, 1 IC, 2 SC) may act on a FIFO (receive, send, SC's handling of a
// message, a DIS top-up) at cycle p only when every other stage's earliest possible next action
// is later than p, or at p with a higher stage index (ties: OS, then IC, then SC). So every FIFO
// action happens in (cycle, stage) order, whatever the scheduler's quantum.
//
// The scheduler gives the stage it runs a horizon: the last cycle at which it has its turn,
// from the other stages' earliest actions (pe.cpp). What the running stage does can only move
// the others earlier through what it sends them (or the room it frees for them), so a send or
// a pop lowers its own horizon here; a FIFO gate past the horizon answers "not now" and the
// processor blocks until the scheduler hands it the turn again.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

namespace nesshi::machine {

struct Turns {
    static constexpr std::uint64_t kAlways = ~std::uint64_t{0};
    std::array<std::uint64_t, 3> horizon{kAlways, kAlways, kAlways};
    std::array<bool, 3> wants_room{}; // the stage waits for room on a full FIFO (set with the horizon)

    bool may_act(int stage, std::uint64_t p) const { return p <= horizon[stage]; }
    // `stage` made it possible for `other` to act from cycle `from` on: `other` goes first at `from`
    // when its index is lower.
    void enables(int stage, int other, std::uint64_t from) {
        horizon[stage] = std::min(horizon[stage], other < stage ? from - 1 : from);
    }
};

// A lower bound on a stage's next FIFO action: `own` from what it holds now (its clock, words
// already sent to it, room already free), else no earlier than `floor` and than another stage j's
// next action + via[j] (what j may still send it, or the room j may free). kNever: none.
struct Bound {
    static constexpr std::uint64_t kNever = ~std::uint64_t{0};
    std::uint64_t own = kNever, floor = 0;
    std::array<std::uint64_t, 3> via{kNever, kNever, kNever};
};

// Every stage's bound: the least over the chains of actions that could lead to its next one, the
// least fixed point of e[i] = min(own, max(floor, e[k] + via[k])). Each step adds at least one
// cycle, so no chain visits a stage twice: two rounds over the six pairs reach it (Bellman-Ford
// over three stages, the same answer as Dijkstra's rule, without its data-dependent picks).
// `without`: leave that stage out, for the stage about to run.
inline std::array<std::uint64_t, 3> settle(const std::array<Bound, 3>& b, int without) {
    constexpr std::uint64_t kNever = Bound::kNever;
    // Three scalars, not an array: a store at the computed index `without`, and vector loads that
    // straddled two bounds, could not be forwarded from the stores before them (stalls that made
    // this a fifth of the scheduler's step).
    std::uint64_t e0 = without == 0 ? kNever : b[0].own, e1 = without == 1 ? kNever : b[1].own,
                  e2 = without == 2 ? kNever : b[2].own;
    auto relax = [&](std::uint64_t& e, int i, std::uint64_t from, int k) {
        const std::uint64_t via = b[static_cast<std::size_t>(i)].via[static_cast<std::size_t>(k)];
        if (i == without || via == kNever || from == kNever) return;
        e = std::min(e, std::max(b[static_cast<std::size_t>(i)].floor, from + via));
    };
    for (int round = 0; round < 2; ++round) {
        relax(e0, 0, e1, 1), relax(e0, 0, e2, 2);
        relax(e1, 1, e0, 0), relax(e1, 1, e2, 2);
        relax(e2, 2, e0, 0), relax(e2, 2, e1, 1);
    }
    return {e0, e1, e2};
}

} // namespace nesshi::machine
