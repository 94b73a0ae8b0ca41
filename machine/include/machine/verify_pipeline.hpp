// A software-pipelined loop checked against its sequential meaning on the simulator: both run on
// random data (memory, registers, FIFO words) and must agree. Used by `nesshi pipeline` and the
// Python module, so that code that differs from its meaning is never handed out.
#pragma once

#include "isa/machine.hpp"
#include "sched/pipeline.hpp"

#include <string>
#include <string_view>

namespace nesshi::machine {

// What was checked, region by region ("equals the sequential one (memory, registers and FIFO
// words) on random data for trip counts 0, 1, ..."); throws base::Error located at `filename` on
// the first difference. `r` is pipeline_source(text, filename, m, po).
std::string verify_pipeline(std::string_view text, const std::string& filename, const isa::Machine& m,
                            const sched::PipelineOptions& po, const sched::PipelineResult& r);

} // namespace nesshi::machine
