// The machine a source file is assembled for, the same way in every command that takes one.
#pragma once

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"

#include <string>
#include <string_view>

namespace nesshi::cli {

// `override` (-m, a preset or TOML file) when given, else the `# machine: NAME` first line of
// `text`, else os.
inline isa::Machine source_machine(const std::string& override, std::string_view text) {
    if (!override.empty()) return isa::load_machine(override);
    const std::string name = assembler::header_machine(text);
    return isa::load_machine(name.empty() ? "os" : name);
}

} // namespace nesshi::cli
