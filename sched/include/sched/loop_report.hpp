// The report for a hand-written loop (`nesshi loop FILE.s`): for each loop of an assembled
// program (a code label whose block ends in a branch back to it), and for each pass of a loop
// threaded through `jr` dispatch (a label whose address the program stores, `li` then `sw`, as
// a dispatch table's entry: the path from it through unconditional jumps, falling through
// conditional exits, to its `jr`; one pass is one iteration of that kind), the achieved II, every
// resource's use against its capacity, ResMII with the resource that binds, RecMII (register
// recurrences, and memory ones through a store and a load off one stepped base register) with the
// critical circuit spelled out, the verdict, register lifetimes and MaxLive per file, and the
// modulo reservation table. Text like TI's pipeline information block, and JSON.
//
//   const auto loops = sched::analyse_loops(object, isa::load_machine("os"));
//   for (const sched::LoopReport& l : loops) fmt::print("{}", l.text());
#pragma once

#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::sched {

struct ResourceUse {
    std::string name;       // "iu0", "IRF reads", "FPRF writes"
    std::uint32_t used = 0; // per iteration
    std::uint32_t capacity = 0; // per iteration at the achieved II
};

struct Lifetime {
    std::string reg;
    int cycles = 0; // from the write's issue to its last read (reads in the next iteration add II)
    int born = 0;   // the body cycle its write issues in
    int file = 0;   // 0 IRF, 1 FPRF
};

// One cycle of the reservation table as data (LoopReport::mrt is its text).
struct TableRow {
    struct Op {
        std::string slot, op, op_class; // "fpu0", "fmul", "fmul" (the machine description's class name)
        int stage = -1; // a software-pipelined loop's: the iteration stage the op belongs to (-1: loop control, or none)
    };
    std::vector<Op> ops;
    int reads[2] = {0, 0}, writes[2] = {0, 0}; // register file ports used, IRF and FPRF
};

struct LoopReport {
    std::string label;
    std::string source;            // "file:line" of the label's bundle
    std::uint32_t first = 0, last = 0; // first and last bundle of its path
    int bundles = 0, ii = 0;       // ii: bundles + the taken-branch bubble
    int ops = 0;
    int res_mii = 0, rec_mii = 0;
    std::string res_binding;       // "slots {iu0, iu1}: 7 ops / 2 = 4"
    std::vector<std::string> critical; // the ops of the critical circuit, in order
    int critical_latency = 0, critical_distance = 0;
    std::vector<ResourceUse> resources;
    std::vector<Lifetime> lifetimes;
    int max_live[2] = {0, 0};
    std::uint32_t file_size[2] = {0, 0};
    std::vector<std::string> mrt;  // one line per body bundle
    std::vector<TableRow> table;   // the same, as data
    std::vector<std::string> slots;            // the machine's issue slots, in order
    std::uint32_t read_ports[2] = {0, 0}, write_ports[2] = {0, 0};
    std::string machine;
    std::string verdict;
    bool dispatch = false;             // a pass of a jr-dispatched loop (a body), not a branch-back loop
    std::vector<std::string> through;  // the labels its path jumps to after its first bundle
    std::string span;                  // its bundles as ranges in path order: "50-59, 97-120, 40-49"

    std::string text() const;
    std::string json() const;
    // A picture: the reservation table (slots and ports by cycle, ops coloured by class, or by
    // iteration stage when the table has stages) above the register lifetimes on a cycle axis
    // marked every II (sched/src/loop_svg.cpp).
    std::string svg() const;
};

// Every loop of the program, or only the one at `label` (empty: all). Throws std::runtime_error
// when `label` is not a loop.
std::vector<LoopReport> analyse_loops(const isa::ObjectFile& obj, const isa::Machine& m, const std::string& label = "");

} // namespace nesshi::sched
