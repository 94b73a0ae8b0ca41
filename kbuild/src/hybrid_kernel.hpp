// The hybrid IC kernel: the dispatch kernel's bodies (ic/intersect.pk, three primitives in flight
// across kinds) for short voxel lists, the per-kind software-pipelined loops
// (ic/intersect.loops.pk) for long ones. Both are scheduled for the machine on their own; this
// joins the two scheduled texts (the loops file says how, at its `hybrid_start`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace nesshi::kbuild::detail {

struct HybridText {
    std::optional<std::string> text; // none: `loops` does not say how (no `hybrid_start`), or `why`
    std::string why;                 // why two kernels that say how cannot be joined
};

// The joined text (before legalizing the joins for the machine): `dispatch` with the loops'
// start (their jump table renamed IC_JUMPS_L) and `hybrid_start` between its start and its
// next_ray, and the loops' entry, runs and end after it (each label the dispatch kernel also
// defines, such as done, return and hit, suffixed _loops); its label "lists_long_N"
// (kernels::abi::kListsLongPrefix) asks the host for LOOPS records on lists of at least
// `long_from` references. Refused (`why`) where a register one part sets up once is written by
// the other, or read by the dispatch kernel after the loops' start set it to another value.
HybridText hybrid_kernel_text(const std::string& dispatch, const std::string& loops, std::uint32_t long_from);

// `text` (a hybrid's, legalized or not) for lists of at least `long_from` references instead.
std::string with_long_from(const std::string& text, std::uint32_t long_from);

} // namespace nesshi::kbuild::detail
