// A scheduled kernel's loop as JSON: one form for the stats JSON (machine.kernels.*.loops) and
// the disk cache of scheduled kernels, which reads it back.
#pragma once

#include "machine/kernel_build.hpp"

#include <nlohmann/json.hpp>

namespace nesshi::machine {

nlohmann::json loop_json(const KernelLoop& l);
// Throws nlohmann::json::exception on another layout.
KernelLoop loop_from_json(const nlohmann::json& j);

} // namespace nesshi::machine
