// How a kernel was built, as JSON: a loop in the one form the stats JSON
// (machine.kernels.*.loops) and the disk cache share, and the whole build as the disk cache
// keeps it and reads it back.
#pragma once

#include "kbuild/kernel_build.hpp"

#include <nlohmann/json.hpp>

namespace nesshi::kbuild {

nlohmann::json loop_json(const KernelLoop& l);
nlohmann::json build_json(const KernelBuild& b);
// Both throw nlohmann::json::exception on another layout.
KernelLoop loop_from_json(const nlohmann::json& j);
KernelBuild build_from_json(const nlohmann::json& j);

} // namespace nesshi::kbuild
