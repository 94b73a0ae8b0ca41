// `nesshi dis`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_dis(CLI::App& app) {
    auto* cmd = app.add_subcommand("dis", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi dis: not built yet", 2); });
}
} // namespace nesshi::cli
