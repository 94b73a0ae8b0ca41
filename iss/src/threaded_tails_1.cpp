// The threaded handler tables of tails 1-3 (handlers.hpp, tail_table).
#include "handlers.hpp"

namespace nesshi::iss::detail {
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<1>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<2>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<3>(bool);
} // namespace nesshi::iss::detail
