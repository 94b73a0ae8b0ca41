// Shared by `nesshi sim`, `nesshi debug` and `nesshi demo`: load an object or assemble a source.
//
// A `.s` file is assembled on the fly for the machine named by --machine, else by its first-line
// comment `# machine: NAME`, else `os`. Anything else is read as an object file.
#pragma once

#include "status.hpp"
#include "errors.hpp"
#include "source_machine.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "iss/program.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace nesshi::cli {

// Prints the assembler's diagnostics to stderr; throws (errors.hpp) on any loading problem.
inline std::shared_ptr<const iss::Program> load_sim_input(const std::string& path, const std::string& machine) {
    bool source = path.size() > 2 && path.compare(path.size() - 2, 2, ".s") == 0;
    if (!source) return iss::load_program_file(path, machine);
    const std::string text = base::read_file(path);
    const isa::Machine m = source_machine(machine, text);
    auto r = assembler::assemble_string(text, path, m, {});
    status("{}", r.diagnostics);
    if (!r.ok) throw Reported(kExitInput);
    return iss::load_program(r.object, m);
}

} // namespace nesshi::cli
