// Random loops in linear assembly, for the pipeliner's property test and benchmark: loads from
// two input arrays, `compute_ops` operations drawn from the operation table (every compute row
// whose operands are registers or small immediates) over earlier values and live-in registers,
// an accumulator (a recurrence through a physical register), two stores and an induction step.
// The data sit at the start of the machine's first memory region; the trip register is r9.
#pragma once

#include "isa/machine.hpp"

#include <cstdint>
#include <string>

namespace nesshi::sched {

std::string random_linear_loop(std::uint64_t seed, const isa::Machine& m, int compute_ops);

// The same as a `.pipeline while` loop: it leaves when x[k] exceeds a random threshold or after
// 40 iterations; the exit test, the step, the accumulator and the stores sit at random places
// around it, and the loads are `.speculate` or not at random.
std::string random_while_loop(std::uint64_t seed, const isa::Machine& m, int compute_ops);

} // namespace nesshi::sched
