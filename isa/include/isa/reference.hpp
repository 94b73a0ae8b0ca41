// The ISA reference (docs/isa.md), generated from the operation table and the presets.
#pragma once

#include <string>

namespace nesshi::isa {
std::string isa_reference_markdown();
}
