// Internal to the pipeliner: the assembly text of a modulo-scheduled region with its registers
// (a counted loop's guard, short path, prologue, kernel and epilogue; a while loop's prologue,
// kernel copies and exit paths).
#pragma once

#include "pipeline_registers.hpp"
#include "trip.hpp"

#include "isa/machine.hpp"

#include <string>

namespace nesshi::sched::pipe {

struct Emitted {
    std::string code;
    int stages = 1;
};

// `trip`, `uid`, `trip_min`, `shape`: a counted loop's trip register, label prefix, `.trip`
// minimum, and the shape of its code (set when given); a while loop needs only `uid`.
Emitted emit_region(const Region& r, const Graph& g, const Schedule& s, const Allocation& a, const isa::Machine& m,
                    const std::string& uid, int trip_min = 0, CountedShape* shape = nullptr);

} // namespace nesshi::sched::pipe
