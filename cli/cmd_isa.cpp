// `nesshi isa`: the operation table and machine presets, as a reference.
#include "commands.hpp"
#include "errors.hpp"

#include "isa/machine.hpp"
#include "isa/reference.hpp"

#include <fmt/core.h>

namespace nesshi::cli {
void add_isa(CLI::App& app) {
    auto* cmd = app.add_subcommand("isa", "Print the ISA reference (operations, encodings, presets)");
    struct Opts { bool markdown = false; std::string machine; };
    auto opts = std::make_shared<Opts>();
    cmd->add_flag("--markdown", opts->markdown, "Print docs/isa.md exactly as generated");
    cmd->add_option("--machine-toml", opts->machine, "Print a preset's TOML description (os, ic, seq, ...)");
    cmd->callback([opts] {
        if (!opts->machine.empty()) {
            auto text = isa::preset_text(opts->machine);
            if (text.empty()) throw UsageError(fmt::format("no preset named '{}'", opts->machine));
            fmt::print("{}", text);
            return;
        }
        fmt::print("{}", isa::isa_reference_markdown());
    });
}
} // namespace nesshi::cli
