// `nesshi loop FILE.s`: the report of each hand-written loop in a program (sched/loop_report.hpp).
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "source_machine.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "isa/machine.hpp"
#include "sched/loop_report.hpp"

#include <fmt/core.h>

#include <cstdio>
#include <filesystem>

namespace nesshi::cli {

void add_loop(CLI::App& app) {
    auto* cmd = app.add_subcommand("loop", "Report each loop of an assembly file: II, bounds, resources, lifetimes");
    struct Args {
        std::string input, machine, label, json, svg;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("input", a->input, "Assembly source (.s)")->required();
    cmd->add_option("-m,--machine", a->machine, "Machine (default: the file's '# machine:' line, else os)");
    cmd->add_option("--label", a->label, "Only the loop at this label");
    cmd->add_option("--json", a->json, "Also write the reports as JSON to FILE ('-': the JSON on stdout, the text on stderr)");
    cmd->add_option("--svg", a->svg, "Also draw each loop's reservation table and register lifetimes as SVG: FILE for one "
                                     "loop, else FILE with each loop's label before its extension (loop.svg: loop-body.svg)");
    cmd->callback([a] {
        std::FILE* report = stdout_output({{"--json", a->json}}) ? stderr : stdout;
        check_output(a->json);
        refuse_stdout("--svg", a->svg, "each loop's picture is a file of its own");
        check_output(a->svg);
        const std::string text = base::read_file(a->input);
        const isa::Machine m = source_machine(a->machine, text);
        const assembler::AsmResult r = assembler::assemble_string(text, a->input, m, {});
        status("{}", r.diagnostics);
        if (!r.ok) throw Reported(kExitInput);
        const std::vector<sched::LoopReport> loops = sched::analyse_loops(r.object, m, a->label);
        if (loops.empty())
            fmt::print(report, "{}: no loops: straight-line code (no label whose block ends in a branch back to it, and no "
                       "stored label address that a jr could dispatch to)\n", a->input);
        std::string json = "[";
        for (std::size_t k = 0; k < loops.size(); ++k) {
            fmt::print(report, "{}{}", k ? "\n" : "", loops[k].text());
            json += (k ? ",\n" : "\n") + loops[k].json();
        }
        if (!a->json.empty()) base::write_file(a->json, json + "\n]\n");
        for (const sched::LoopReport& l : loops) {
            if (a->svg.empty()) break;
            const std::filesystem::path p(a->svg);
            const std::string file = loops.size() == 1 ? a->svg
                                                       : (p.parent_path() / (p.stem().string() + "-" + l.label + p.extension().string())).string();
            base::write_file(file, l.svg());
        }
    });
}

} // namespace nesshi::cli
