// The threaded handler tables of tails 4-6 (handlers.hpp, tail_table).
#include "handlers.hpp"

namespace nesshi::iss::detail {
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<4>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<5>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<6>(bool);
} // namespace nesshi::iss::detail
