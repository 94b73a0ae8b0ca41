// The synthetic workloads of the kernel report (machine::Workload): grids and rays for the 3DDDA
// kernels, voxels of one shape kind and rays for the intersection kernels, run to completion.
#pragma once

#include "machine/kernel_report.hpp"
#include "machine/runner.hpp"
#include "kernel_measure.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace nesshi::machine {

struct WorkloadRun {
    std::unique_ptr<KernelRunner> run;
    double rays = 0;
    double primitives = 0; // primitive tests the rays asked for (an intersection workload)
    KernelBuild build;     // how its kernel was made (from sources; empty for a program given)
};

// The 3DDDA kernel for `machine` (kernels::kernel_path) on the empty grid, then on the sparse
// grid, whose grid and rays continue the empty run's random stream (seed 5).
struct DdaRuns {
    WorkloadRun empty, sparse;
};
// `role` is the stage the kernel is written for (os or seq: kernels::kernel_path), `machine` the
// description it runs on.
DdaRuns run_dda(const kernels::SourceSet& sources, const std::string& role, const isa::Machine& machine);

// The intersection kernel for `machine` on a primitive workload (seed 7).
WorkloadRun run_intersect(const kernels::SourceSet& sources, const std::string& role, const isa::Machine& machine, Workload w);

// The same on a program already assembled (its machine is the program's).
DdaRuns run_dda(const std::shared_ptr<const iss::Program>& prog);
WorkloadRun run_intersect(const std::shared_ptr<const iss::Program>& prog, Workload w);

bool is_grid(Workload w);

} // namespace nesshi::machine
