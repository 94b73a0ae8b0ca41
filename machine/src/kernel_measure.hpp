// What a candidate kernel is chosen by (internal to src/machine; defined beside the kernel
// report's workloads, in workloads.cpp).
#pragma once

#include "iss/program.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace nesshi::machine {

// Processing plus communication cycles of `prog` (a kernel at `path`: "os/dda.s", "ic/intersect.s")
// over every workload of its kind in the kernel report.
std::uint64_t workload_busy_cycles(const std::shared_ptr<const iss::Program>& prog, const std::string& path);

} // namespace nesshi::machine
