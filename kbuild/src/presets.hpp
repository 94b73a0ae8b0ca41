// Internal: the preset machine descriptions, parsed once per process (src/stage_machine.cpp).
#pragma once
#include "isa/machine.hpp"

#include <string_view>
#include <vector>

namespace nesshi::kbuild::detail {

const std::vector<isa::Machine>& presets(); // in isa::preset_names() order
const isa::Machine* preset(std::string_view name); // null when `name` is no preset's

} // namespace nesshi::kbuild::detail
