// Internal to the pipeliner: the dependence graph of a region's operations (registers, memory
// with the region's aliasing rules, a while loop's exit) as a Ddg (ddg.hpp: its recurrence
// bounds, circuits and longest paths), the values stage scheduling moves, and the report's
// critical circuit and alias hint.
#pragma once

#include "pipeline_region.hpp"
#include "stages.hpp"

#include "sched/ddg.hpp"

#include "isa/encoding.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nesshi::sched::pipe {

using Edge = Dep; // ddg.hpp

struct Node {
    isa::Instr instr;
    int latency = 1;
    bool mem = false, store = false;
    int base = -1;            // memory ops: the base register
    bool speculative = false; // a load whose base is declared `.speculate` (it may run past the exit)
    bool adjusted = false;    // memory op on an induction register: offset moved, no register edge
    int width = 4;
};

struct Induction {
    int reg = -1;
    int op = -1;      // the addi
    std::int64_t step = 0;
};

struct Graph {
    std::vector<Node> nodes;
    Ddg ddg; // its nodes are `nodes`
    std::vector<Induction> inductions;
    // What the code before the region leaves: integer registers holding known constants, and the
    // trip count when it is one of them (constants_at).
    std::map<int, std::int64_t> entry;
    std::optional<std::int64_t> trip;
    const Induction* induction_of(int reg) const {
        for (const Induction& i : inductions)
            if (i.reg == reg) return &i;
        return nullptr;
    }
};

// The bytes memory op x touches over the whole loop, [lo, hi), when its base is a known constant
// at entry stepped only by its induction and the trip count is known; nullopt otherwise.
std::optional<std::pair<std::int64_t, std::int64_t>> extent(const Graph& g, int x);

// Whether memory ops x (iteration i) and y (iteration i + d) may touch the same bytes.
bool may_alias(const Graph& g, const Region& r, int x, int y, int d);

// Whether op i of a while loop has an effect a discarded iteration must not have: a store, a
// FIFO word, a load whose base is not declared `.speculate` (it could fault past the end), or a
// write of a physical register other than an induction (the exit path corrects inductions).
bool side_effect(const Graph& g, int i, const std::function<bool(int, isa::RegFile, int)>& is_virtual);

// Speculation that is safe by construction: no side effect issues before every earlier exit test
// has been decided. Iteration i's exit test precedes the side effects of iteration i + 1 (and so
// of every later one), and those of iteration i written after the test. One bundle later: the
// ops in the bundle of a taken branch still execute.
void add_exit_edges(Graph& g, const Region& r, const std::function<bool(int, isa::RegFile, int)>& is_virtual);

// The region's dependences: registers (true, anti and output, across iterations for carried
// values), memory (by base, offset and induction, within kMaxMemoryDistance iterations, unless
// `.noalias`) and, for a while loop, its exit (add_exit_edges). `entry`: the constants the code
// before the region leaves in integer registers.
Graph build_graph(const Region& r, const std::vector<isa::Instr>& instrs, const isa::Machine& m,
                  const std::vector<OpVirtuals>& op_virtuals, const std::map<int, std::int64_t>& entry = {});

// The values the virtual and physical registers carry from op to op (the true edges, one value
// per writer and register), for stage scheduling.
std::vector<StageValue> stage_values(const Graph& g);

// That circuit (edge indices into g.ddg.edges), op by op with each edge's latency and why it is
// there, e.g. "flw (line 11) -[2: true %x]-> fmul (line 12) ... : 9 cycles over 1 iteration"; ""
// when none binds above 1.
std::string critical_circuit(const Graph& g, const Region& r, const std::vector<int>& circuit);

// When the RecMII's circuit runs through memory edges between two base registers that may alias
// (no `.noalias` for them), what declaring them apart would give: "`.noalias r1, r2` (if the
// arrays never overlap) removes it: RecMII 1"; "" otherwise.
std::string alias_hint(const Graph& g, const std::vector<int>& circuit);

} // namespace nesshi::sched::pipe
