// The compiled runs of a decoded program as C++ source: one function per straight run of bundles,
// with each operation's registers and immediates as constants, calling only the helpers of
// iss/src/compiled.hpp (Counts, op<>, end<>, jump<>, jump_to<>, stop, leave), so the semantics stay
// those of isa::kOps; each bundle's tail is checked against the threaded handler the Program chose.
// The build compiles the built-in kernels' runs with it (machine/tools/gen_compiled_runs.cpp).
#pragma once

#include "iss/program.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::iss {

// `parts` + 1 files of C++: [0] declares the runs, holds their tables and defines the
// iss::CompiledProgram `kCompiled_<id>` in namespace `registry_namespace` (named `spec`); [1] ..
// [parts] the runs in order, in parts of about equal size, so that one big program is several
// compilations. Throws std::runtime_error on a program the form cannot hold (a bundle without an
// op, a run that ends going straight on, a tail that is not the threaded form's).
std::vector<std::string> compiled_runs_source(const Program& prog, const std::string& spec, const std::string& id,
                                              std::uint32_t parts, const std::string& registry_namespace);

} // namespace nesshi::iss
