// `nesshi pipeline FILE.sa`: linear assembly in, a software-pipelined loop out (sched/pipeline.hpp),
// optionally verified by simulation against the region's sequential meaning.
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "ranges.hpp"
#include "source_machine.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "isa/machine.hpp"
#include "iss/differential.hpp"
#include "sched/pipeline.hpp"

#include <fmt/core.h>

#include <cstdio>

namespace nesshi::cli {

namespace {

struct PipelineArgs {
    std::string input, machine, out, sequential;
    int ii = 0;
    double exact = 0;
    bool verify = false, quiet = false;
};

constexpr int kWhileRuns = 64; // random data sets for a while loop: each exits somewhere else

void verify_while_loop(const PipelineArgs& a, const std::string& text, const isa::Machine& m, const sched::PipelineOptions& po,
                       iss::DiffOptions d, const sched::PipelineResult& r) {
    d.observe = {r.iteration_register};
    const sched::WhileVerification v = sched::verify_while(
        text, a.input, m, po, kWhileRuns,
        [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip, std::uint64_t seed, std::uint32_t& exits) {
            iss::DiffOptions o = d;
            o.seed = seed;
            std::vector<std::uint32_t> seen;
            auto diff = iss::run_differential(lin, pip, m, o, &seen);
            exits = seen.empty() ? 0 : seen[0];
            return diff;
        });
    if (v.failure) throw base::Error(base::SourceLoc(a.input), fmt::format("verification failed: {}", *v.failure));
    std::string exits;
    for (std::uint32_t e : v.exits) exits += (exits.empty() ? "" : ", ") + std::to_string(e);
    fmt::print(stderr, "{}: verified: the pipelined loop equals the sequential one (memory and registers) on {} random data "
                       "sets, exiting after {} iterations; {} of its {} exit paths taken\n",
               a.input, kWhileRuns, exits, v.paths.size(), v.path_count);
}

void run_pipeline(const PipelineArgs& a) {
    refuse_stdout("--sequential", a.sequential, "stdout holds the pipelined code or its report; give a file");
    check_outputs({a.out, a.sequential});
    const std::string text = base::read_file(a.input);
    const isa::Machine m = source_machine(a.machine, text);
    sched::PipelineOptions po;
    po.ii = a.ii;
    po.exact_seconds = a.exact;
    const sched::PipelineResult r = sched::pipeline_source(text, a.input, m, po);
    const bool to_file = !a.out.empty() && a.out != "-"; // -o -: stdout, as without -o
    if (to_file) base::write_file(a.out, r.pipelined);
    if (!a.sequential.empty()) base::write_file(a.sequential, r.linear);
    if (!a.quiet) fmt::print("{}", to_file ? r.report : r.pipelined);
    base::flush_stdout();
    if (!a.verify) return;
    iss::DiffOptions d;
    d.registers = r.source_registers;
    if (r.is_while) return verify_while_loop(a, text, m, po, d, r);
    const std::vector<std::uint32_t> trips = sched::verification_trips(r);
    const auto diff = sched::verify(text, a.input, m, po, trips,
                                    [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip) {
                                        return iss::run_differential(lin, pip, m, d);
                                    });
    if (diff) throw base::Error(base::SourceLoc(a.input), fmt::format("verification failed: {}", *diff));
    std::string list;
    for (std::uint32_t t : trips) list += (list.empty() ? "" : ", ") + std::to_string(t);
    fmt::print(stderr, "{}: verified: the pipelined loop equals the sequential one (memory and registers) for trip "
                       "counts {}\n", a.input, list);
}

} // namespace

void add_pipeline(CLI::App& app) {
    auto* cmd = app.add_subcommand("pipeline", "Software-pipeline the .pipeline region of a linear-assembly file");
    auto a = std::make_shared<PipelineArgs>();
    cmd->add_option("input", a->input, "Linear assembly (.sa): a .pipeline TRIP (or .pipeline while) ... .endpipeline region")->required();
    cmd->add_option("-m,--machine", a->machine, "Machine (default: the file's '# machine:' line, else os)");
    cmd->add_option("-o,--output", a->out, "Write the pipelined assembly to FILE and print the report (default, or '-': the code on stdout)");
    cmd->add_option("--sequential", a->sequential, "Also write the region's sequential meaning (the reference "
                                                   "--verify compares with) to FILE (a file, never stdout)");
    cmd->add_option("--ii", a->ii, "Schedule at this initiation interval only")->check(between(1, 4096));
    cmd->add_option("--exact", a->exact, "When the II is above the MII, branch and bound over the smaller IIs for up to SECONDS; "
                                         "the report says whether the II is proven optimal")
        ->check(between(0.0, 86400.0));
    cmd->add_flag("--verify", a->verify, "Run sequential and pipelined code on random data for several trip counts "
                                         "and compare memory and registers");
    cmd->add_flag("-q,--quiet", a->quiet, "Print nothing but errors and the verification result");
    cmd->callback([a] { run_pipeline(*a); });
}

} // namespace nesshi::cli
