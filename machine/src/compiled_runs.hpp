// The compiled runs of the built-in kernels (iss/compiled.hpp), generated at build time by
// machine/tools/gen_compiled_runs.cpp into the library nesshi_compiled_runs.
#pragma once

namespace nesshi::machine::detail {

// Registers every compiled program with the ISS (once; thread-safe). assemble_kernel calls it
// before it loads a program, so that the program finds its table.
void register_compiled_runs();

} // namespace nesshi::machine::detail
