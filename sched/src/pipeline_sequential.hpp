// Internal to the pipeliner: a region's sequential meaning, the reference the pipelined code is
// verified against and the text the assembler turns into the exact operations the graph is built
// from. Each virtual register stands on a placeholder register of its own where there are enough.
#pragma once

#include "pipeline_region.hpp"

#include "isa/machine.hpp"

#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nesshi::sched::pipe {

// A region's sequential meaning: each virtual on its placeholder register (placeholder_registers),
// a while loop's iterations counted in the lowest free register.
struct Sequential {
    std::vector<std::string> placeholder_name;      // per virtual
    std::set<std::pair<int, int>> placeholders;     // (file, reg) of every placeholder
    std::vector<OpVirtuals> op_virtuals;            // per op: its operands' placeholders -> virtual
    std::string iteration_register;                 // a while loop's
    std::string loop;                               // the text
};

// `named`: the registers the file names (placeholders avoid them); `uid`: the region's label prefix.
Sequential sequential_meaning(const Region& r, const std::set<std::pair<int, int>>& named, const isa::Machine& m,
                              std::string_view filename, const std::string& uid);

} // namespace nesshi::sched::pipe
