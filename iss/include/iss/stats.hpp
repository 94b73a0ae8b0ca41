// Statistics views, derived from a processor's raw counters (always on, see processor.hpp).
//
// A bundle's unit and port usage is static, so one execution counter per bundle gives most
// figures; only waits, stalls, taken branches and the write-port histogram are counted as
// they happen. Every view prints as text (stats_text) and as JSON (stats_json). Fields:
//
// Run summary
//   machine               machine description name; slots = its issue slots
//   cycles                total cycles = processing_cycles + communication_cycles + wait_cycles
//   processing_cycles     cycles issuing a bundle without FIFO operations, plus branch
//                         bubbles and memory stalls
//   communication_cycles  cycles issuing a bundle that contains send/recv (paper's "communication")
//   wait_cycles           cycles a bundle could not issue: recv on an empty channel / send on a full one
//   bubble_cycles         branch-penalty cycles after taken branches (part of processing)
//   stall_cycles          extra memory-latency / cache stall cycles (part of processing)
//   bundles               bundles issued; processing_bundles: those without FIFO operations
//   ops                   operations issued, NOPs not counted; processing_ops: in processing bundles
//   ilp                   processing_ops / processing_cycles (the paper's "operations per bundle
//                         over processing time")
//   ops_per_bundle        ops / bundles
//   utilization           ilp / slots (the paper's unit utilisation; the JSON spells it as the
//                         machine's stats JSON does)
//   ilp_hist[n]           issued bundles with n operations (nops not counted)
//   taken_branches        taken control transfers
//   words_received, words_sent   FIFO words
// units[] (one per issue slot)
//   name, ops             operations issued in that slot in processing bundles
//   comm_ops              operations issued in that slot in communication bundles
//   utilization           ops / processing_cycles
// ports[] (one per register file: IRF, FPRF)
//   read_ports, write_ports   from the machine description
//   reads, writes         register reads at issue; writes counted in the cycle they land
//   read_utilization      reads / (read_ports * cycles); write_utilization likewise
//   read_hist[n], write_hist[n]   cycles in which n ports were used (over all cycles)
// regions[] (a region runs from a code label to the next label)
//   label, first, end     bundle range [first, end)
//   cycles, processing_cycles, communication_cycles, wait_cycles, bundles, ops, ilp
//                         as above, restricted to bundles of the region (bubbles and stalls go to
//                         the bundle that caused them, waits to the bundle that waited)
// hot[] (bundles by execution count, most executed first)
//   pc, name (label+offset), source (file:line), exec, ops, text (the bundle disassembled)
#pragma once

#include "iss/processor.hpp"

#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::iss {

struct UnitStats {
    std::string name;
    uint64_t ops = 0, comm_ops = 0;
    double utilisation = 0;
};

struct PortStats {
    std::string file;
    uint32_t read_ports = 0, write_ports = 0;
    uint64_t reads = 0, writes = 0;
    double read_utilisation = 0, write_utilisation = 0;
    std::vector<uint64_t> read_hist, write_hist;
};

struct RegionStats {
    std::string label;
    uint32_t first = 0, end = 0;
    uint64_t cycles = 0, processing_cycles = 0, communication_cycles = 0, wait_cycles = 0;
    uint64_t bundles = 0, ops = 0, processing_ops = 0;
    double ilp = 0;
};

struct HotBundle {
    uint32_t pc = 0;
    std::string name, source, text;
    uint64_t exec = 0;
    uint32_t ops = 0;
};

struct Stats {
    std::string machine;
    uint32_t slots = 0;
    uint64_t cycles = 0, processing_cycles = 0, communication_cycles = 0, wait_cycles = 0;
    uint64_t bubble_cycles = 0, stall_cycles = 0;
    uint64_t bundles = 0, processing_bundles = 0, ops = 0, processing_ops = 0;
    uint64_t taken_branches = 0, words_received = 0, words_sent = 0;
    double ilp = 0, ops_per_bundle = 0, utilisation = 0;
    std::vector<uint64_t> ilp_hist; // issued bundles by operation count
    std::vector<UnitStats> units;
    std::vector<PortStats> ports;
    std::vector<RegionStats> regions;
    std::vector<HotBundle> hot;
};

// `hot` limits the hot-spot listing.
Stats compute_stats(const Processor& p, size_t hot = 10);
std::string stats_text(const Stats& s);
// Adds `add` (another processor running the same program on the same machine, e.g. another PE's
// stage) into `into`: counts and histograms summed, ratios recomputed; `hot` is left out (a
// merge of per-processor top lists would not be the top list of the sum). `into` may be empty.
void accumulate(Stats& into, const Stats& add);
nlohmann::json stats_json(const Stats& s);

} // namespace nesshi::iss
