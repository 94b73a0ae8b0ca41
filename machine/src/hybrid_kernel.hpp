// The hybrid IC kernel: the dispatch kernel's bodies (ic/intersect.pk, three primitives in flight
// across kinds) for short voxel lists, the per-kind software-pipelined loops
// (ic/intersect.loops.pk) for long ones. Both are scheduled for the machine on their own; this
// joins the two scheduled texts (the loops file says how, at its `hybrid_start`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace nesshi::machine::detail {

// The joined text (before legalizing the joins for the machine): `dispatch` with the loops'
// start (their jump table renamed IC_JUMPS_L) and `hybrid_start` between its start and its
// next_ray, and the loops' entry, runs and end (done, return, hit renamed *_loops) after it; its
// label "lists_long_N" (kernels::abi::kListsLongPrefix) asks the host for LOOPS records on lists
// of at least `long_from` references. None when `loops` has no `hybrid_start`.
std::optional<std::string> hybrid_kernel_text(const std::string& dispatch, const std::string& loops, std::uint32_t long_from);

} // namespace nesshi::machine::detail
