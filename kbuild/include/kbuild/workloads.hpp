// The synthetic workloads of the kernel report (machine/kernel_report.hpp): grids and rays for the
// 3DDDA kernels, voxels of one shape kind and rays for the intersection kernels, run to completion.
// The kernel build weighs candidate kernels on them.
#pragma once

#include "kbuild/runner.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace nesshi::kbuild {

// The synthetic inputs. Grids: rays from random points outside aimed into the box; each VISIT is
// answered with a RETURN (no hit). Primitives: one voxel listing 40 shapes of one kind, rays
// aimed at the origin (or past the shapes, for SpheresMissed).
enum class Workload {
    EmptyGrid,       // 40^3, empty, 300 rays: every step is a loop step
    SparseGrid,      // 20^3, 3% full, 300 rays: VISITs and RETURNs (continues EmptyGrid's random stream)
    Triangles,       // one-sided triangles, 200 rays
    Spheres,         // one-sided plain spheres, 200 rays
    SpheresMissed,   // the same spheres, 200 rays that miss them
    TwoSidedSpheres, // two-sided spheres, 200 rays
    Cylinders,       // one-sided cylinders of length 4 along z, 200 rays
    ShortLists,      // 64 voxels of 1-12 mixed shapes (the SPD scenes' 2.5-21 per voxel), 2000 rays
};

// Processing plus communication cycles of `prog` (a kernel at `path`: "os/dda.s", "ic/intersect.s")
// over every workload of its kind: what a candidate kernel is chosen by.
std::uint64_t workload_busy_cycles(const std::shared_ptr<const iss::Program>& prog, const std::string& path);

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

} // namespace nesshi::kbuild
