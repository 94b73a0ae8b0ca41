// `nesshi debug`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_debug(CLI::App& app) {
    auto* cmd = app.add_subcommand("debug", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi debug: not built yet", 2); });
}
} // namespace nesshi::cli
