// `nesshi pipeline FILE.sa`: linear assembly in, a software-pipelined loop out (sched/pipeline.hpp),
// optionally verified by simulation against the region's sequential meaning.
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "ranges.hpp"
#include "source_machine.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"

#include <filesystem>
#include "isa/machine.hpp"
#include "machine/verify_pipeline.hpp"
#include "sched/pipeline.hpp"

#include <fmt/core.h>

#include <cstdio>

namespace nesshi::cli {

namespace {

struct PipelineArgs {
    std::string input, machine, out, sequential, json, svg;
    int ii = 0;
    double exact = 0;
    bool shorten = false;
    bool no_verify = false, quiet = false;
};

void run_pipeline(const PipelineArgs& a) {
    refuse_stdout("--sequential", a.sequential, "stdout holds the pipelined code or its report; give a file");
    refuse_stdout("--json", a.json, "stdout holds the pipelined code or its report; give a file");
    refuse_stdout("--svg", a.svg, "stdout holds the pipelined code or its report; give a file");
    check_outputs({a.out, a.sequential, a.json, a.svg});
    const std::string text = base::read_file(a.input);
    const isa::Machine m = source_machine(a.machine, text);
    sched::PipelineOptions po;
    po.ii = a.ii;
    po.exact_seconds = a.exact;
    if (a.shorten) po.shorten = sched::PipelineOptions::Shorten::Always;
    const sched::PipelineResult r = sched::pipeline_source(text, a.input, m, po);
    // Verified before anything is written: code that differs from its meaning is never output.
    const std::string verdict =
        a.no_verify ? std::string("not run (--no-verify)") : machine::verify_pipeline(text, a.input, m, po, r);
    const std::string report = r.report + fmt::format("#   verification: {}\n", verdict);
    const std::string pipelined = fmt::format("# machine: {}\n", m.reference()) + report + r.code;
    const bool to_file = !a.out.empty() && a.out != "-"; // -o -: stdout, as without -o
    if (to_file) base::write_file(a.out, pipelined);
    if (!a.sequential.empty()) base::write_file(a.sequential, r.linear);
    if (!a.json.empty()) {
        std::string json = "[";
        for (std::size_t k = 0; k < r.loops.size(); ++k) json += (k ? ",\n" : "\n") + r.loops[k].json();
        base::write_file(a.json, json + "\n]\n");
    }
    for (std::size_t k = 0; k < r.loops.size() && !a.svg.empty(); ++k) { // FILE, then FILE-2, FILE-3 ... for more regions
        const std::filesystem::path p(a.svg);
        base::write_file(k == 0 ? a.svg : (p.parent_path() / fmt::format("{}-{}{}", p.stem().string(), k + 1, p.extension().string())).string(),
                         r.loops[k].svg);
    }
    if (!to_file) fmt::print("{}", pipelined); // the data: printed even with -q
    else if (!a.quiet) fmt::print("{}", report);
    base::flush_stdout();
    if (!a.no_verify) status("{}: verified: the pipelined loop{} {}\n", a.input, r.regions > 1 ? "s:" : "", verdict);
}

} // namespace

void add_pipeline(CLI::App& app) {
    static const std::string kVerifyHelp = "Verify (the default; kept for old scripts)";
    auto* cmd = app.add_subcommand("pipeline", "Software-pipeline the .pipeline region of a linear-assembly file");
    auto a = std::make_shared<PipelineArgs>();
    cmd->add_option("input", a->input, "Linear assembly (.sa): a .pipeline TRIP (or .pipeline while) ... .endpipeline region")->required();
    cmd->add_option("-m,--machine", a->machine, "Machine (default: the file's '# machine:' line, else os)");
    cmd->add_option("-o,--output", a->out, "Write the pipelined assembly to FILE and print the report (default, or '-': the code on stdout)");
    cmd->add_option("--sequential", a->sequential, "Also write the region's sequential meaning (the reference "
                                                   "--verify compares with) to FILE (a file, never stdout)");
    cmd->add_option("--json", a->json, "Also write each region's schedule as JSON to FILE (II, bounds, stages, "
                                       "unroll and, with .trip, the whole-run cycles it was chosen by)");
    cmd->add_option("--svg", a->svg, "Also draw the schedule as SVG: the modulo reservation table, ops coloured by "
                                     "iteration stage, register ports per row, lifetimes (FILE; a second region FILE-2, ...)");
    cmd->add_option("--ii", a->ii, "Schedule at this initiation interval only")->check(between(1, 4096));
    cmd->add_option("--exact", a->exact, "When the II is above the MII, search every table at the smaller IIs for up to SECONDS; "
                                         "the report says whether the II is proven optimal")
        ->check(between(0.0, 86400.0));
    cmd->add_flag("--shorten", a->shorten, "Search for the shortest iteration at the II found with the solver (up to about "
                                           "a second per loop) whatever the trip count; by default only where .trip says "
                                           "runs are short enough for the fill and drain to matter");
    cmd->add_flag("--no-verify", a->no_verify, "Skip the verification: by default the sequential and pipelined code run on "
                                               "random data (memory, FIFO words) for several trip counts and must agree in "
                                               "memory, registers and words sent, or nothing is written")
        ->excludes(cmd->add_flag("--verify", kVerifyHelp));
    cmd->add_flag("-q,--quiet", a->quiet, "Print no report (code on stdout is still printed), only errors and the verification result");
    cmd->callback([a] { run_pipeline(*a); });
}

} // namespace nesshi::cli
