// Lock-step: run the fast and the checked engine side by side and report the first divergence.
#pragma once

#include "iss/processor.hpp"

#include <cstdint>
#include <optional>

namespace nesshi::iss {

struct LockstepResult {
    Status status = Status::Running;   // common status at the end (Faulted on divergence)
    std::optional<Fault> fault;        // the checked engine's fault, or the divergence
    uint64_t bundles = 0;              // bundles compared
};

// `fast` and `checked` must run the same program from the same state with equivalent channels
// (each its own). After every bundle: pc, cycle, status, all registers and in-flight writes
// are compared; at the end also memory contents and counters. Stops at halt, fault, block,
// divergence or after max_cycles. When the checked engine faults on a dynamic rule the fast
// engine trusts, `fast` has already issued the faulting bundle: report `checked`'s state (its
// cycle count is the one the other engines give for a fault), as `nesshi sim` does.
LockstepResult run_lockstep(Processor& fast, Processor& checked, uint64_t max_cycles);

} // namespace nesshi::iss
