// --os-machine, --ic-machine, --seq-machine: the stages' machine descriptions, the same three
// options (and help) on every command that runs or measures the kernels.
#pragma once
#include <CLI/CLI.hpp>

#include <string>

namespace nesshi::cli {

inline void add_stage_machine_options(CLI::App* cmd, std::string& os, std::string& ic, std::string& seq,
                                      const std::string& group = "Options") {
    cmd->add_option("--os-machine", os, "machine of the OS stage, model V: preset or TOML (default os)")->group(group);
    cmd->add_option("--ic-machine", ic, "machine of the IC stage, model V: preset or TOML (default ic)")->group(group);
    cmd->add_option("--seq-machine", seq, "sequential machine of models S and M, and SC prices (default seq)")
        ->group(group);
}

} // namespace nesshi::cli
