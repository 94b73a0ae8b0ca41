// Test support for the kernels: assemble a kernel file, run it on the ISS, random inputs.
#pragma once

#include "kernels/abi.hpp"
#include "kernels/messages.hpp"
#include "kernels/image.hpp"
#include "kernels/sources.hpp"
#include "kbuild/runner.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/channel.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace nesshi::kernels::test {

// Assembles the built-in kernel <rel> for `machine` once per process and shares the program.
inline std::shared_ptr<const iss::Program> kernel_program(const std::string& rel, const std::string& machine) {
    static std::map<std::string, std::shared_ptr<const iss::Program>> cache;
    const std::string key = rel + "@" + machine;
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    auto prog = kbuild::assemble_kernel(embedded(), rel, machine);
    cache.emplace(key, prog);
    return prog;
}

// One processor running a kernel, with its input channel 0 and output channels 1 and 2.
struct Rig : kbuild::KernelRunner {
    Rig(const std::string& rel, const std::string& machine, iss::Engine engine)
        : KernelRunner(kernel_program(rel, machine), engine) {}
    Rig(std::shared_ptr<const iss::Program> prog, iss::Engine engine) : KernelRunner(std::move(prog), engine) {}
    // Runs until the kernel waits for input; fails the test on a fault or halt.
    void run() { REQUIRE_NOTHROW(KernelRunner::run(50'000'000)); }
    std::uint32_t peek32(std::uint32_t addr) const {
        std::uint32_t v = 0;
        REQUIRE(proc->memory().peek(addr, 4, v));
        return v;
    }
};

inline std::uint32_t fbits(float f) { return abi::bits(f); }


} // namespace nesshi::kernels::test
