// `nesshi kernels`: the cycle report of the kernels (built for each machine) measured on the ISS
// (machine/kernel_report.hpp holds the measurements, the paper's figures and the goals).
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "stage_machines.hpp"

#include "base/write_file.hpp"
#include "machine/kernel_report.hpp"

#include <fmt/core.h>

#include <memory>
#include <string>

namespace nesshi::cli {

void add_kernels(CLI::App& app) {
    auto* cmd = app.add_subcommand("kernels", "Cycle report of the kernels as built for each machine (measured on the ISS)");
    auto json = std::make_shared<std::string>();
    auto dir = std::make_shared<std::string>();
    cmd->add_option("--json", *json, "Also write the table as JSON to FILE ('-': the JSON on stdout, the table on stderr)");
    cmd->add_option("--kernels", *dir, "A folder of kernel sources to measure instead of the built-in ones");
    auto names = std::make_shared<StageMachineNames>();
    add_stage_machine_options(cmd, *names, "Options",
                              "measure the os rows on this machine: preset or TOML (default os)",
                              "measure the ic rows on this machine (default ic)", "measure the seq rows on this machine (default seq)");
    auto loops = std::make_shared<bool>(false);
    cmd->add_flag("--loops", *loops,
                  "After the table, the pipeliner's report of each loop scheduled for the machines (as nesshi pipeline prints it)");
    cmd->callback([json, dir, names, loops] {
        machine::KernelMachines machines;
        names->load(machines.os, machines.ic, machines.seq);
        const bool json_on_stdout = stdout_output({{"--json", *json}});
        check_output(*json);
        const machine::KernelReport report =
            machine::kernel_report(dir->empty() ? kernels::embedded() : kernels::from_directory(*dir), machines);
        fmt::print(json_on_stdout ? stderr : stdout, "{}", report.text());
        if (*loops) fmt::print(json_on_stdout ? stderr : stdout, "{}", report.loops_text());
        if (!json->empty()) base::write_file(*json, report.json(*loops) + "\n");
    });
}

} // namespace nesshi::cli
