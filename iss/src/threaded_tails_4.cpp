// The threaded handler tables of tails 10-12 (handlers.hpp, tail_table).
#include "handlers.hpp"

namespace nesshi::iss::detail {
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<10>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<11>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<12>(bool);
} // namespace nesshi::iss::detail
