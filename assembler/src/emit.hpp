// Second-pass output: data bytes from data directives, and the object file.
#pragma once

#include "layout.hpp"

#include "isa/object.hpp"

namespace nesshi::assembler {

// Evaluates .word/.half/.byte/.float values into the data sections' bytes.
void fill_data(Layout& layout, Diagnostics& diags);

// Reports a non-empty data section that no memory region of `m` holds whole (the loader would
// refuse the object).
void check_data_regions(const Layout& layout, const isa::Machine& m, Diagnostics& diags);

// Marks `.global` names; reports undefined or non-label names.
void apply_globals(Layout& layout, Diagnostics& diags);

// Builds the object: code words in slot order within each bundle with the end-of-bundle bit,
// non-empty data sections, labels sorted by (kind, value, name), the line table.
isa::ObjectFile build_object(const Layout& layout, const isa::Machine& m);

} // namespace nesshi::assembler
