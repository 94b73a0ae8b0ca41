// `nesshi render`: placeholder until its issue lands.
#include "commands.hpp"

namespace nesshi::cli {
void add_render(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "(not yet built)");
    cmd->callback([] { throw CLI::RuntimeError("nesshi render: not built yet", 2); });
}
} // namespace nesshi::cli
