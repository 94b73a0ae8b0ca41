// How a stage's kernel was built for its machine (machine/runner.hpp builds it; machine::Stats
// and the stats JSON report it).
#pragma once

#include <string>

namespace nesshi::machine {

// How a kernel was built for its machine.
struct KernelBuild {
    std::string source;   // the file assembled: "kernels/os/dda.s", or its ".pk" when scheduled for the machine
    std::string machine;  // the machine's name
    bool scheduled = false; // its straight-line blocks were scheduled for the machine
    int blocks = 0;         // how many
    int nops = 0;           // nop bundles inserted into its hand-scheduled code for the machine's latencies
    std::string choice;     // when the committed kernel was also a candidate: which was kept, and the cycles of both
};

} // namespace nesshi::machine
