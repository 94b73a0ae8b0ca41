// --os-machine, --ic-machine, --seq-machine: the stages' machine descriptions, the same three
// options (and help) on every command that runs or measures the kernels. The names given are
// loaded once, when the command runs (after --help and the required arguments, which CLI11 checks
// after option callbacks), into kbuild::StageMachine values that everything downstream shares.
#pragma once
#include "machine/machine.hpp"
#include "kbuild/stage_machine.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace nesshi::cli {

struct StageMachineNames {
    std::string os, ic, seq; // as given; "" = not given (the preset stays)

    // Loads the ones given into the three machines (a description that does not load throws, with
    // its file and line).
    void load(kbuild::StageMachine& os_machine, kbuild::StageMachine& ic_machine, kbuild::StageMachine& seq_machine) const {
        if (!os.empty()) os_machine = kbuild::StageMachine(os);
        if (!ic.empty()) ic_machine = kbuild::StageMachine(ic);
        if (!seq.empty()) seq_machine = kbuild::StageMachine(seq);
    }
    void load(machine::Options& mo) const { load(mo.os_machine, mo.ic_machine, mo.seq_machine); }
};

inline void add_stage_machine_options(CLI::App* cmd, StageMachineNames& names, const std::string& group = "Options",
                                      const char* os_help = "machine of the OS stage, model V: preset or TOML (default os)",
                                      const char* ic_help = "machine of the IC stage, model V: preset or TOML (default ic)",
                                      const char* seq_help =
                                          "sequential machine of models S and M, and SC prices (default seq)") {
    cmd->add_option("--os-machine", names.os, os_help)->group(group);
    cmd->add_option("--ic-machine", names.ic, ic_help)->group(group);
    cmd->add_option("--seq-machine", names.seq, seq_help)->group(group);
}

} // namespace nesshi::cli
