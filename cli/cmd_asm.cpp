// `nesshi asm`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_asm(CLI::App& app) {
    auto* cmd = app.add_subcommand("asm", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi asm: not built yet", 2); });
}
} // namespace nesshi::cli
