// Lower bounds on the initiation interval of a loop body, each with what binds it.
//
// ResMII: every subset S of issue slots must issue, each iteration, the ops whose class only
// slots of S accept (Hall's condition), so II >= |those ops| / |S| for every S; each register
// file's reads and writes over its read and write ports; and the bundles the ops' reads need when
// packed into bundles of that many read ports (ops reading more than half of them never share a
// bundle: on 3 ports, 48 ops reading 2 floats each need 48 bundles, not 98/3). RecMII of a region taken as a loop
// body: the circuit of its dependence graph (ddg.hpp) with the most latency per pass. The modulo scheduler (pipeline.hpp) and the kernel
// report (machine/kernel_report.hpp) use these; neither restates the machine's rules.
//
//   const isa::Machine m = isa::load_machine("os");
//   std::vector<isa::Instr> body = ...;                     // one iteration, e.g. decoded bundles
//   const sched::ResBound r = sched::res_mii(m, body, sched::kLoopControl);
//   r.cycles;  // 4.0: cycles per pass at least (unrounded)   r.ii(); // 4
//   r.binds;   // "FPRF write ports 8/2 = 4"
//   const sched::RecBound c = sched::region_rec_mii(m, ops_with_their_bundles);
//   c.binds;   // "r4: add (1) -> lbu (1) = 2 cycles"
#pragma once

#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "isa/ops.hpp"
#include "sched/ddg.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace nesshi::sched {

// Operations a scheduler adds to the listed ones (e.g. loop control): `count` ops of class `cls`,
// each reading and writing that many registers of each file (the modulo table counts them against
// the ports as it does the listed ops').
struct ExtraOps {
    isa::OpClass cls = isa::OpClass::Alu;
    int count = 1;
    std::array<int, isa::kNumRegFiles> reads{}, writes{};
};
// The kernel's loop control: `bnez counter, kernel` (reads the counter) and
// `addi counter, counter, -1` (reads and writes it).
inline constexpr std::array<ExtraOps, 2> kLoopControl = {ExtraOps{isa::OpClass::Branch, 1, {1, 0}, {0, 0}},
                                                         ExtraOps{isa::OpClass::Alu, 1, {1, 0}, {1, 0}}};

struct ResBound {
    double cycles = 0; // the largest of ops / slots over slot subsets, accesses / ports and packed reads per file
    // "slots {iu0,iu1}: 7 ops / 2 = 3.5", "FPRF write ports 8/2 = 4",
    // "FPRF read ports 98/3 packed: 48 ops read more than half of them = 48"; "" when no op
    std::string binds;
    int ii() const;    // the smallest whole II it allows: ceil(cycles), at least 1
};

// ResMII of `ops` (nops count nothing) plus `extra`. Ties name the first found: slot subsets
// in mask order, then IRF reads, IRF writes, FPRF reads, FPRF writes.
ResBound res_mii(const isa::Machine& m, std::span<const isa::Instr> ops, std::span<const ExtraOps> extra = {});

struct RecBound {
    double cycles = 0;              // the recurrence's latency per pass (over its passes); 0 when none
    std::string reg;                // the register it carries: "r4" (or "memory true r5")
    std::vector<std::size_t> chain; // indices into the ops: the read of the carried value first, its write last
    std::string binds;              // "r4: add (1) -> lbu (1) = 2 cycles"; "" when none
};

// RecMII of a region as a loop body: its ops (in issue order, `bundle` the cycle each issues in
// from the pass's first, 0) repeated every `bundles` cycles (at least up to the last op's) and the
// taken branch's bubble, the bound of scheduled_loop_ddg (ddg.hpp) on its
// circuit of the largest latency per pass. Control dependences (a branch deciding the next pass)
// are not edges.
RecBound region_rec_mii(const isa::Machine& m, std::span<const BodyOp> ops, std::uint32_t bundles = 0);

} // namespace nesshi::sched
