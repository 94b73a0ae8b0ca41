// The one bundle checker: every resource rule a single bundle must obey on a machine.
//
// Collects the bundle's reads and writes per register file once, then runs one small check
// per rule and reports every violation (not only the first). The assembler turns violations
// into diagnostics, the loader rejects objects with any, and the ISS relies on it for the
// static part of its checking. Rules that span bundles (latency hazards, writes from earlier
// bundles landing in the same cycle) belong to the assembler's flow analysis and the ISS.
#pragma once

#include "isa/encoding.hpp"
#include "isa/machine.hpp"

#include <span>
#include <string>
#include <vector>

namespace nesshi::isa {

enum class Rule : uint8_t {
    SlotRange,   // slot index beyond the machine's slots
    SlotClass,   // the slot's unit does not accept the operation's class
    SlotTwice,   // two operations in one slot
    RegRange,    // register number beyond the file's size
    ReadPorts,   // more register reads in the bundle than read ports
    WritePorts,  // more writes landing in one cycle than write ports
    DupWrite,    // two writes to one register landing in the same cycle
};
std::string_view rule_name(Rule r);

struct Violation {
    Rule rule;
    int op = -1;    // index in the bundle of the operation at fault
    int other = -1; // another operation involved, or -1
    std::string message;
    std::string note; // about `other`, when set
};

std::vector<Violation> check_bundle(const Machine& m, std::span<const Instr> ops);
// check_bundle(m, ops).empty(), without building the messages: for schedulers, which ask it for
// every place they try.
bool bundle_fits(const Machine& m, std::span<const Instr> ops);

// Assigns issue slots: ops with pinned[i] >= 0 keep that slot, the rest get the first slots
// that accept them (a bipartite matching, so an assignment is found whenever one exists).
// Returns false when none exists.
bool assign_slots(const Machine& m, std::span<Instr> ops, std::span<const int> pinned);

// Per-bundle resource usage, for listings and statistics.
struct BundleUsage {
    std::array<uint32_t, kNumRegFiles> reads{};
    std::array<uint32_t, kNumRegFiles> writes{}; // all writes, whatever their landing cycle
    uint32_t ops = 0;                            // non-nop operations
};
BundleUsage bundle_usage(std::span<const Instr> ops);

} // namespace nesshi::isa
