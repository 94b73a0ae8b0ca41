// How a stage's kernel was built for its machine (kbuild/runner.hpp builds it; machine::Stats
// and the stats JSON report it).
#pragma once

#include <string>
#include <vector>

namespace nesshi::kbuild {

// A `.pipeline` loop of a kernel, modulo-scheduled for the machine.
struct KernelLoop {
    int line = 0;          // of its .pipeline in the source
    bool is_while = false; // `.pipeline while` (else counted)
    int ii = 0, mii = 0, stages = 0, unroll = 1;
    int rec_mii = 0; // its recurrences as written, the exit test's control dependences included
    int iteration = 0, longest_path = 0; // one iteration's cycles, first issue to last landing, and its longest path
};

// How a kernel was built for its machine.
struct KernelBuild {
    std::string source;   // the file assembled: "kernels/os/dda.s", or its ".pk" when scheduled for the machine
    std::string machine;  // the machine's name
    bool scheduled = false; // its straight-line blocks were scheduled for the machine
    int blocks = 0;         // how many
    int blocks_shortest = 0; // of them, proven shortest (sched::block_schedule)
    int nops = 0;           // nop bundles inserted into its hand-scheduled code for the machine's latencies
    std::string choice;     // when the committed kernel was also a candidate: which was kept, and the cycles of both
    int candidates = 1;     // kernels measured against each other for the choice (1: none)
    std::vector<KernelLoop> loops; // its loops as scheduled (empty when the committed kernel was kept)
    std::string loop_report;       // the pipeliner's report of those loops (`nesshi pipeline`'s), one block each
};

} // namespace nesshi::kbuild
