// The threaded handler tables of tails 7-9 (handlers.hpp, tail_table).
#include "handlers.hpp"

namespace nesshi::iss::detail {
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<7>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<8>(bool);
template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<9>(bool);
} // namespace nesshi::iss::detail
