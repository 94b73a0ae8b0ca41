// `nesshi demo`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_demo(CLI::App& app) {
    auto* cmd = app.add_subcommand("demo", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi demo: not built yet", 2); });
}
} // namespace nesshi::cli
