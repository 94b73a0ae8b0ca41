// The dependence graph every scheduler and bound in sched/ works on: ops are its nodes (by
// index), each edge says "`to` issues at least `latency` cycles after `from`, `distance`
// iterations earlier" (t_to >= t_from + latency - distance x II). One type and one set of
// graph algorithms (recurrence bounds, critical circuits, longest paths) for
// - the block scheduler (block.hpp): a straight-line block in program order, distance 0;
// - the modulo scheduler (pipeline.hpp): a linear-assembly loop body, with carried values,
//   memory disambiguated by the region's rules and a while loop's exit (built in the pipeliner);
// - the loop and kernel reports (loop_report.hpp, bounds.hpp): a scheduled body repeated every
//   II cycles, where the landings decide which write a read sees.
//
//   const sched::Ddg g = sched::scheduled_loop_ddg(m, body_ops, ii);
//   g.rec_mii();   // smallest II the recurrences admit
//   g.critical();  // the edges of a circuit that sets it
#pragma once

#include "isa/encoding.hpp"
#include "isa/machine.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace nesshi::sched {

enum class DepKind : std::uint8_t {
    True,   // a read after the write it sees
    Anti,   // a write after a read of the old value
    Output, // writes of one register in order
    Memory, // a store and another access that may touch the same bytes
    Fifo,   // words of one channel in order
    Order,  // a branch or halt after every earlier op
    Exit,   // a while loop's exit test before a side effect
};

// Memory dependences are looked for up to this many iterations apart.
inline constexpr int kMaxMemoryDistance = 16;

struct Dep {
    int from = 0, to = 0;
    int latency = 0;  // to issues >= from + latency - distance x II
    int distance = 0; // iterations
    DepKind kind = DepKind::True;
    std::string why = {}; // "true %x", "memory true, bases r1 and r2 may alias", "fifo order"
};

// A circuit's latency over its distance: the II it needs is latency / distance.
struct CycleRatio {
    int latency = 0, distance = 0;
    double value() const { return distance > 0 ? static_cast<double>(latency) / distance : 0; }
};

struct Ddg {
    int nodes = 0;
    std::vector<Dep> edges;

    // No circuit has latency - II x distance > 0: every recurrence fits this II.
    bool admits(int ii) const;
    // The smallest II admitted (1 when the graph has no circuit).
    int rec_mii() const;
    // A circuit positive at `ii` (so it binds at ii + 1), as edge indices in order; empty when none.
    std::vector<int> circuit_above(int ii) const;
    // A circuit that sets rec_mii(); empty when rec_mii() is 1.
    std::vector<int> critical() const;
    // The circuit whose latency / distance is largest (the exact recurrence bound, which rec_mii
    // rounds up), as edge indices; empty when the graph has no circuit of positive latency.
    std::vector<int> max_ratio_circuit() const;
    CycleRatio ratio(std::span<const int> circuit) const;
    // Each op's longest path at this II (latency - distance x II per edge, self edges left out):
    // out of it to any op (`out`: its height) or into it from any op (its depth).
    std::vector<int> longest_paths(int ii, bool out) const;
    // The edges into each op (indices into `edges`, in edge order).
    std::vector<std::vector<int>> edges_into() const;
};

// A straight-line block in program order (the block scheduler's view): true, anti and output
// edges per register (a write may issue before an earlier read when it lands after it), loads
// and stores in order as far as they may alias (every pair: the block's addresses are not
// analysed), FIFO words of a channel in order, and each branch or halt after every earlier op,
// which may land up to `grace` cycles after it (its bubble). Distances are 0; latency may be
// negative (an anti or output edge).
Ddg block_ddg(const isa::Machine& m, std::span<const isa::Instr> ops, int grace);

// One operation of a scheduled region and the cycle it issues in; a region lists its ops in
// issue order.
struct BodyOp {
    isa::Instr instr;
    std::uint32_t bundle = 0;
};

// A scheduled body run as a loop every `ii` cycles (op cycles are `bundle`s from 0): each read
// sees the write that landed last by its cycle, from this pass or an earlier one (its distance);
// a store and a later load off one base register stepped by one `addi` per pass (or not at all)
// that touch common bytes, within kMaxMemoryDistance passes, latency 1. Only true dependences: what bounds the
// loop as it is scheduled.
Ddg scheduled_loop_ddg(const isa::Machine& m, std::span<const BodyOp> ops, int ii);

} // namespace nesshi::sched
