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

} // namespace nesshi::machine
