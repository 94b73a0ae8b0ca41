// Faults: what stops a run, and the report printed for it.
//
// A report names the rule broken, the cycle and PC, the bundle disassembled with its source
// file:line, and one note per operation or register involved:
//
//   fault: write-ports: 3 FPRF writes land in cycle 4; os has 2 FPRF write ports
//     at cycle 3, pc 4 (target), t.s:9
//     bundle 4: { fpu0: fadd f1, f2, f3 ; fpu1: fadd f4, f5, f6 }
//     note: fdiv f9, f1, f2 (bundle 0, issued in cycle 0, t.s:3) writes f9 in cycle 4
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::iss {

class Program;

enum class FaultKind : uint8_t {
    BadPc,        // control reached an address outside the code (branch, jr, fall-through)
    MemRange,     // load/store outside every memory region
    MemAlign,     // load/store address not aligned to its width
    NoChannel,    // send/recv on a channel the host did not attach
    Deadlock,     // recv on an empty channel that will never be fed (or all processors blocked)
    CycleLimit,   // --max-cycles reached
    InflightRead, // checked engine: a source register has a write still in flight
    WritePorts,   // checked engine: more writes land in one cycle than the file has ports
    DupWrite,     // checked engine: two writes to one register land in the same cycle
    WriteOrder,   // checked engine: a write lands before an earlier-issued one to its register
    Divergence,   // lock-step: the engines disagree
};
std::string_view fault_rule(FaultKind k); // "write-ports", ...

struct Fault {
    FaultKind kind = FaultKind::BadPc;
    uint64_t cycle = 0;
    uint32_t pc = 0;
    std::string message;            // one line: what went wrong, naming registers/addresses
    std::vector<std::string> notes; // the operations and registers involved
};

// The multi-line report (ends with a newline).
std::string format_fault(const Program& prog, const Fault& f);

} // namespace nesshi::iss
