// A build without the compiled runs (cmake -DNESSHI_COMPILED_RUNS=OFF): every kernel runs threaded.
#include "compiled_runs.hpp"

namespace nesshi::machine::detail {
void register_compiled_runs() {}
} // namespace nesshi::machine::detail
