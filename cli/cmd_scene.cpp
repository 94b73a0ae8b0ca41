// `nesshi scene`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_scene(CLI::App& app) {
    auto* cmd = app.add_subcommand("scene", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi scene: not built yet", 2); });
}
} // namespace nesshi::cli
