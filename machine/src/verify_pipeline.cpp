// Pipelined loops against their sequential meaning: counted loops over the trip counts that reach
// every path, while loops over random data sets that exit at many iterations.
#include "machine/verify_pipeline.hpp"

#include "base/error.hpp"
#include "iss/differential.hpp"

#include <fmt/format.h>

namespace nesshi::machine {
namespace {

constexpr int kWhileRuns = 64; // random data sets for a while loop: each exits somewhere else

std::string verify_while_loop(const std::string& filename, const isa::Machine& m, iss::DiffOptions d,
                              const sched::PipelineResult& r) {
    d.observe = {r.iteration_register};
    const sched::WhileVerification v = sched::verify_while(
        r, filename, m, kWhileRuns,
        [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip, std::uint64_t seed, std::uint32_t& exits) {
            iss::DiffOptions o = d;
            o.seed = seed;
            std::vector<std::uint32_t> seen;
            auto diff = iss::run_differential(lin, pip, m, o, &seen);
            exits = seen.empty() ? 0 : seen[0];
            return diff;
        });
    if (v.failure) throw base::Error(base::SourceLoc(filename), fmt::format("verification failed: {}", *v.failure));
    std::string exits;
    for (std::uint32_t e : v.exits) exits += (exits.empty() ? "" : ", ") + std::to_string(e);
    return fmt::format("equals the sequential one (memory, registers and FIFO words) on {} random data sets, exiting after {} "
                       "iterations; {} of its {} exit paths taken", kWhileRuns, exits, v.paths.size(), v.path_count);
}

std::string verify_loop(const std::string& filename, const isa::Machine& m, const sched::PipelineResult& r) {
    iss::DiffOptions d;
    d.registers = r.source_registers;
    if (r.is_while) return verify_while_loop(filename, m, d, r);
    const std::vector<std::uint32_t> trips = sched::verification_trips(r);
    const auto diff = sched::verify(r, filename, m, trips, [&](const isa::ObjectFile& lin, const isa::ObjectFile& pip) {
        return iss::run_differential(lin, pip, m, d);
    });
    if (diff) throw base::Error(base::SourceLoc(filename), fmt::format("verification failed: {}", *diff));
    std::string list;
    for (std::uint32_t t : trips) list += (list.empty() ? "" : ", ") + std::to_string(t);
    return fmt::format("equals the sequential one (memory, registers and FIFO words) on random data for trip counts {}", list);
}

} // namespace

std::string verify_pipeline(std::string_view text, const std::string& filename, const isa::Machine& m,
                            const sched::PipelineOptions& po, const sched::PipelineResult& r) {
    if (r.regions == 1) return verify_loop(filename, m, r);
    std::string verdict;
    for (int k = 0; k < r.regions; ++k) { // one region at a time, the others sequential
        sched::PipelineOptions one = po;
        one.region = k;
        verdict += fmt::format("{}region {}: {}", k ? "; " : "", k + 1,
                               verify_loop(filename, m, sched::pipeline_source(text, filename, m, one)));
    }
    return verdict;
}

} // namespace nesshi::machine
