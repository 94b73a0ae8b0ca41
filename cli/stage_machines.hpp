// --os-machine, --ic-machine, --seq-machine: the stages' machine descriptions, the same three
// options (and help) on every command that runs or measures the kernels. Each is loaded as it is
// parsed (machine::StageMachine), once: a description that does not load is the command's error.
#pragma once
#include "machine/stage_machine.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace nesshi::cli {

inline void add_stage_machine_options(CLI::App* cmd, machine::StageMachine& os, machine::StageMachine& ic,
                                      machine::StageMachine& seq, const std::string& group = "Options",
                                      const char* os_help = "machine of the OS stage, model V: preset or TOML (default os)",
                                      const char* ic_help = "machine of the IC stage, model V: preset or TOML (default ic)",
                                      const char* seq_help =
                                          "sequential machine of models S and M, and SC prices (default seq)") {
    auto bind = [&](const char* name, machine::StageMachine& into, const char* help) {
        cmd->add_option_function<std::string>(name, [&into](const std::string& v) { into = machine::StageMachine(v); }, help)
            ->type_name("TEXT")
            ->group(group);
    };
    bind("--os-machine", os, os_help);
    bind("--ic-machine", ic, ic_help);
    bind("--seq-machine", seq, seq_help);
}

} // namespace nesshi::cli
