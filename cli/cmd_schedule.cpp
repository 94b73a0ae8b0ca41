// `nesshi schedule FILE`: list-schedule the `#pack begin` ... `#pack end` blocks of an assembly
// file into bundles (sched/block.hpp); everything else is copied.
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "source_machine.hpp"

#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "isa/machine.hpp"
#include "sched/block.hpp"

#include <fmt/core.h>


namespace nesshi::cli {

void add_schedule(CLI::App& app) {
    auto* cmd = app.add_subcommand("schedule", "Bundle the straight-line '#pack begin' ... '#pack end' blocks of a file");
    struct Args {
        std::string input, machine, output;
        std::vector<std::string> includes;
        bool report = false;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("input", a->input, "Assembly source with blocks written one op per line, in order")->required();
    cmd->add_option("-m,--machine", a->machine, "Machine (default: the file's '# machine:' line, else os)");
    cmd->add_option("-o,--output", a->output, "Write the scheduled assembly here (default, or '-': stdout)");
    cmd->add_option("-I,--include-dir", a->includes, "Directory searched by .include");
    cmd->add_flag("--report", a->report, "Print each block's ops and bundles to stderr");
    cmd->callback([a] {
        check_output(a->output);
        const std::string text = base::read_file(a->input);
        const isa::Machine m = source_machine(a->machine, text);
        assembler::AsmOptions opts;
        opts.include_dirs = a->includes;
        const sched::PackResult r = sched::pack_source(text, a->input, m, opts);
        if (a->report)
            for (const sched::BlockStats& b : r.blocks)
                status("{}:{}: {} ops in {} bundles on {}, {}{}\n", a->input, b.line, b.ops, b.bundles, m.name,
                       b.shortest ? "proven shortest" : fmt::format("none has fewer than {}", b.fewest),
                       b.bundles < b.list_bundles ? fmt::format(" (list scheduling: {})", b.list_bundles) : "");
        if (a->output.empty()) fmt::print("{}", r.text);
        else base::replace_file(a->output, r.text); // a failed run leaves the old file whole
    });
}

} // namespace nesshi::cli
