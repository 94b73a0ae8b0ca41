// One kernel on one simulated processor: assemble it, load its memory images, feed its input
// channel and run it until it waits for more. Shared by `nesshi kernels` and the kernel tests.
#pragma once

#include "image.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/channel.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace nesshi::kernels {

// Assembles a kernel source file for `machine`; throws std::runtime_error with the diagnostics.
inline std::shared_ptr<const iss::Program> assemble_kernel(const std::string& path, const std::string& machine) {
    const isa::Machine m = isa::load_machine(machine);
    assembler::AsmResult r = assembler::assemble_file(path, m, {});
    if (!r.ok) throw std::runtime_error(path + ": assembly failed:\n" + r.diagnostics);
    return iss::load_program(r.object, m);
}

// A processor with the ABI's channels: input 0, outputs 1 and 2. Neither copyable nor movable:
// the processor holds the channels' addresses.
class KernelRunner {
  public:
    std::shared_ptr<const iss::Program> prog;
    std::unique_ptr<iss::Processor> proc;
    iss::QueueChannel in, out1, out2;

    explicit KernelRunner(std::shared_ptr<const iss::Program> program, iss::Engine engine = iss::Engine::Fast)
        : prog(std::move(program)), proc(std::make_unique<iss::Processor>(prog, engine)) {
        proc->attach_channel(0, &in);
        proc->attach_channel(1, &out1);
        proc->attach_channel(2, &out2);
    }
    KernelRunner(const KernelRunner&) = delete;
    KernelRunner& operator=(const KernelRunner&) = delete;

    void load(const MemImage& m) {
        if (!m.bytes.empty()) proc->memory().load_data(m.base, m.bytes);
    }
    template <class Words>
    void feed(const Words& w) {
        for (std::uint32_t x : w) in.feed(x, proc->cycle());
    }
    // Runs until the kernel waits on its input channel; a fault, halt or cycle limit throws.
    void run(std::uint64_t max_cycles = 100'000'000) {
        const iss::Status s = proc->run(max_cycles);
        if (s != iss::Status::Blocked || proc->blocked_channel() != 0)
            throw std::runtime_error("kernel did not wait for input: " + proc->fault_report());
    }
};

} // namespace nesshi::kernels
