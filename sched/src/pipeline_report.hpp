// Internal to the pipeliner: the parts of its report drawn from a schedule: the reservation
// table as data and text, the picture (a LoopReport: rows, ports, lifetimes) and a while loop's
// exit lines.
#pragma once

#include "pipeline_graph.hpp"
#include "pipeline_region.hpp"
#include "pipeline_search.hpp"

#include "sched/loop_report.hpp"
#include "sched/pipeline.hpp"

#include "isa/machine.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace nesshi::sched::pipe {

// Each row of the II as data: its ops with the slots they issue in (isa::assign_slots, as the
// emitter bundles them), mnemonic, class and stage; the loop control (counter, branch) in no stage.
// The report's table and the picture are both drawn from it.
std::vector<TableRow> schedule_rows(const Graph& g, const Region& r, const Schedule& s, const isa::Machine& m);

// The rows as the report's modulo reservation table.
std::string mrt_text(const std::vector<TableRow>& rows);

// The schedule as LoopReport draws it: each row of the II with its ops (slot, mnemonic, class,
// stage; loop control in no stage) and the register ports they use (reads at issue, writes where
// they land, mod II), and each virtual register's lifetime from its definition.
LoopReport schedule_picture(const Graph& g, const Region& r, const Schedule& s, std::vector<TableRow> rows,
                            const std::vector<int>& lifetime, const isa::Machine& m, std::string_view filename,
                            const std::string& verdict);

// The report lines of a while loop: how far iterations run ahead of the exit test, what they may
// do there, and the exit paths.
std::string while_report(const Graph& g, const Region& r, const Schedule& s, const PipelineResult& res);

} // namespace nesshi::sched::pipe
