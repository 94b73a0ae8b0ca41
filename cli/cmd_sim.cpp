// `nesshi sim`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_sim(CLI::App& app) {
    auto* cmd = app.add_subcommand("sim", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi sim: not built yet", 2); });
}
} // namespace nesshi::cli
