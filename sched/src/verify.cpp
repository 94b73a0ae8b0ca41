// Verification by simulation (see pipeline.hpp): the sequential meaning and the pipelined code of
// a region, assembled for the machine and handed to a differential run, for several trip counts
// or, for a while loop, on fresh random data per run.
#include "sched/pipeline.hpp"

#include "assembler/assembler.hpp"
#include "base/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>

namespace nesshi::sched {

namespace {

isa::ObjectFile assemble_or_fail(const std::string& text, std::string_view file, const isa::Machine& m,
                                 const std::string& what) {
    const assembler::AsmResult res = assembler::assemble_string(text, file, m, {});
    if (!res.ok || res.warnings > 0)
        throw base::Error(base::SourceLoc(file), fmt::format("the {} does not assemble cleanly:\n{}", what, res.diagnostics));
    return res.object;
}

} // namespace

std::vector<std::uint32_t> verification_trips(const PipelineResult& r) {
    std::set<std::uint32_t> t = {0, 1};
    const int min = r.min_pipelined_trip;
    if (min > 0) t.insert(static_cast<std::uint32_t>(min - 1));
    const int span = std::max(2 * r.unroll + 1, r.unroll * (r.groups + 1));
    for (int k = 0; k <= span; ++k) t.insert(static_cast<std::uint32_t>(min + k));
    if (r.min_trip > 0) { // a count below .trip's minimum is the user's error: never run, as TI's
        t.erase(t.begin(), t.lower_bound(static_cast<std::uint32_t>(r.min_trip)));
        for (int k = 0; k <= span; ++k) t.insert(static_cast<std::uint32_t>(r.min_trip + k));
    }
    return {t.begin(), t.end()};
}

TripPrograms with_trip(const PipelineResult& r, const isa::Machine& m, std::uint32_t n) {
    if (!r.linear_region_at || !r.pipelined_region_at)
        throw std::invalid_argument("with_trip needs the result of one region pipelined (PipelineOptions::region)");
    std::string set = fmt::format("        li {}, {}\n", r.trip_register, n);
    for (std::uint32_t k = 1; k < m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]; ++k) set += "        nop\n";
    return {std::string(r.linear).insert(*r.linear_region_at, set), std::string(r.pipelined).insert(*r.pipelined_region_at, set)};
}

std::optional<std::string> verify(const PipelineResult& r, std::string_view filename, const isa::Machine& m,
                                  const std::vector<std::uint32_t>& trip_counts, const DifferentialRun& run) {
    for (std::uint32_t n : trip_counts) {
        const TripPrograms t = with_trip(r, m, n);
        const isa::ObjectFile lin = assemble_or_fail(t.linear, filename, m, "sequential meaning");
        const isa::ObjectFile pip = assemble_or_fail(t.pipelined, filename, m, "pipelined loop");
        if (auto diff = run(lin, pip)) return fmt::format("trip count {}: {}", n, *diff);
    }
    return std::nullopt;
}


std::string exit_path_name(const PipelineResult& r, std::uint32_t e) {
    // The exit of iteration e is taken at the end of pass e + exit_stage: a prologue pass, or
    // kernel copy (pass - prologue passes) mod unroll.
    const std::uint32_t pass = e + static_cast<std::uint32_t>(r.exit_stage), p = static_cast<std::uint32_t>(r.stages - 1);
    if (pass < p) return fmt::format("prologue pass {}", pass);
    return fmt::format("kernel copy {}", (pass - p) % static_cast<std::uint32_t>(r.unroll));
}

WhileVerification verify_while(const PipelineResult& r, std::string_view filename, const isa::Machine& m, int runs,
                               const WhileRun& run) {
    if (!r.is_while) throw std::invalid_argument("verify_while needs a .pipeline while region");
    const isa::ObjectFile lin = assemble_or_fail(r.linear, filename, m, "sequential meaning");
    const isa::ObjectFile pip = assemble_or_fail(r.pipelined, filename, m, "pipelined loop");
    WhileVerification v;
    v.path_count = std::max(0, r.stages - 1 - r.exit_stage) + r.unroll;
    for (int k = 0; k < runs && !v.failure; ++k) {
        std::uint32_t e = 0;
        const std::uint64_t seed = static_cast<std::uint64_t>(k) + 1;
        if (auto diff = run(lin, pip, seed, e))
            v.failure = fmt::format("data seed {} (the sequential loop exits after {} iterations, {}): {}", seed, e,
                                    exit_path_name(r, e), *diff);
        v.exits.insert(e);
        v.paths.insert(exit_path_name(r, e));
    }
    return v;
}

} // namespace nesshi::sched
