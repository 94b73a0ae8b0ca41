// Exposed-latency analysis over the bundle control-flow graph.
//
// A result is readable `latency` cycles after issue (latency 1: by the next bundle); reads in a
// bundle see the values from before the bundle. A forward data-flow analysis tracks, at each
// bundle, the writes still in flight (register, cycles until it lands, producing op) along every
// path: fall-through, taken branches, jumps, loop back edges. Successors of `jr` are taken
// conservatively as every return point (the bundle after a `jal`) and every code label.
// Reported, with a note at the producing op:
//   - a read of a register whose producer's result has not landed yet;
//   - a write landing before, or in the same cycle as, an in-flight write of the same register
//     issued earlier (writes land in issue order; in one bundle the ISS issues in slot order);
//   - more writes landing in one cycle than the register file has write ports, counting
//     in-flight writes from earlier bundles (same-bundle rules are isa::check_bundle's).
// Also warns when the last bundle can fall through past the end of the code.
#pragma once

#include "layout.hpp"

namespace nesshi::assembler {

void check_hazards(const std::vector<PlacedBundle>& bundles, const isa::Machine& m, Diagnostics& diags,
                   const std::vector<size_t>& code_labels);

} // namespace nesshi::assembler
