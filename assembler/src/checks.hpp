// Per-bundle resource checks: slot assignment (honouring `slot:` pins) and isa::check_bundle,
// turned into diagnostics with a caret at the offending op and a note at the other one.
#pragma once

#include "records.hpp"

#include "isa/machine.hpp"

namespace nesshi::assembler {

// Assigns slots into b.ops[i].instr.slot and reports every violation; false on any error.
bool check_bundle_rules(BundleRec& b, const isa::Machine& m, Diagnostics& diags);

} // namespace nesshi::assembler
