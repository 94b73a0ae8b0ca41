// One kernel on one simulated processor: assemble it, load its memory images, feed its input
// channel and run it until it waits for more. Shared by the machine, the kernel report and the
// kernel tests.
//
//   kernels::SourceSet src = kernels::embedded();
//   kbuild::KernelRunner run(kbuild::assemble_kernel(src, "os/dda.s", "os"));
//   run.load(kernels::os_image(geom, occupancy));  run.run();  run.feed(ray.words());  run.run();
#pragma once

#include "kbuild/kernel_build.hpp"

#include "kernels/image.hpp"
#include "kernels/sources.hpp"

#include "isa/machine.hpp"
#include "iss/channel.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace nesshi::kbuild {

class LazySceneSample; // kbuild/scene_sample.hpp

// Assembles kernel `path` of `sources` ("os/dda.s") for machine `m`; its .include of
// "../abi.inc" resolves inside `sources`. When `m` is not the preset the kernel was scheduled for
// and `sources` hold its source before scheduling ("os/dda.pk"), that source's straight-line
// blocks are scheduled for `m` first (sched/block.hpp), and the hand-scheduled code between them
// gets the nop bundles m's latencies need (sched/legalize.hpp). `build`, if given, says which.
// A machine that is a preset under another name (Machine::same_as) is that preset: its kernels,
// compiled runs and statistics. When more than one kernel is a candidate on `m` (the sources
// scheduled for m, the committed kernel if legal on it; on a preset given a scene, its committed
// kernel and the alternatives such as ic/intersect.loops.pk scheduled for it), the one busy for the fewest cycles is
// kept: on `scene`'s sampled visits when given (an IC kernel for one render; traced only then),
// else on the kernel report's workloads.
// Throws std::runtime_error with the diagnostics.
std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const isa::Machine& m, KernelBuild* build = nullptr,
                                                    const LazySceneSample* scene = nullptr);
std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const std::string& machine);

// Source `pk` ("ic/intersect.loops.pk") scheduled for `machine` and assembled, as assemble_kernel
// builds it when it weighs that candidate (the build compiles the runs of the ones presets take).
std::shared_ptr<const iss::Program> assemble_source(const kernels::SourceSet& sources, const std::string& pk,
                                                    const std::string& machine);

// How an IC kernel wants its voxel lists laid out (kernels::ic_image's layout): kind by kind when
// it defines abi::kListsByKindLabel, the long ones only when it defines "lists_long_N".
kernels::ListLayout list_layout(const iss::Program& p);

// A processor with the ABI's channels (kernels/abi.hpp): input CH_IN, outputs 1 and 2. Neither copyable nor movable:
// the processor holds the channels' addresses.
class KernelRunner {
  public:
    std::shared_ptr<const iss::Program> prog;
    std::unique_ptr<iss::Processor> proc;
    iss::QueueChannel in, out1, out2;

    explicit KernelRunner(std::shared_ptr<const iss::Program> program, iss::Engine engine = iss::Engine::Fast);
    KernelRunner(const KernelRunner&) = delete;
    KernelRunner& operator=(const KernelRunner&) = delete;

    void load(const kernels::MemImage& m) {
        if (!m.bytes.empty()) proc->memory().load_data(m.base, m.bytes);
    }
    template <class Words>
    void feed(const Words& w) {
        for (std::uint32_t x : w) in.feed(x, proc->cycle());
    }
    // Runs until the kernel waits on its input channel; a fault, halt or cycle limit throws.
    void run(std::uint64_t max_cycles = 100'000'000);
};

} // namespace nesshi::kbuild
