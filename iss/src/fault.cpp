// Fault names and the fault report (see fault.hpp).
#include "iss/fault.hpp"

#include "iss/program.hpp"

#include <fmt/core.h>

namespace nesshi::iss {

std::string_view fault_rule(FaultKind k) {
    switch (k) {
    case FaultKind::BadPc: return "bad-pc";
    case FaultKind::MemRange: return "mem-range";
    case FaultKind::MemAlign: return "mem-align";
    case FaultKind::NoChannel: return "no-channel";
    case FaultKind::Deadlock: return "deadlock";
    case FaultKind::CycleLimit: return "cycle-limit";
    case FaultKind::InflightRead: return "inflight-read";
    case FaultKind::WritePorts: return "write-ports";
    case FaultKind::DupWrite: return "dup-write";
    case FaultKind::WriteOrder: return "write-order";
    case FaultKind::Divergence: return "divergence";
    }
    return "?";
}

std::string format_fault(const Program& prog, const Fault& f) {
    std::string out = fmt::format("fault: {}: {}\n", fault_rule(f.kind), f.message);
    std::string where = fmt::format("  at cycle {}, pc {}", f.cycle, f.pc);
    if (std::string name = prog.code_name(f.pc); !name.empty()) where += fmt::format(" ({})", name);
    if (std::string src = prog.source_of(f.pc); !src.empty()) where += ", " + src;
    out += where + "\n";
    if (f.pc < prog.size()) out += fmt::format("  bundle {}: {}\n", f.pc, prog.format_bundle(f.pc));
    for (const auto& n : f.notes) out += fmt::format("  note: {}\n", n);
    return out;
}

} // namespace nesshi::iss
