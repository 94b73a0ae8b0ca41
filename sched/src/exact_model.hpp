// Internal to the schedulers: a counted loop's modulo reservation tables at one II as a
// constraint model (Gecode), searched to the end: every table that keeps the model's rules is
// found, or none exists. Plain data in, rows and stages out; pipeline_exact.cpp builds the
// problem from a dependence graph and a machine. A straight-line block is the same model with one
// pass: its length is the II, every op in stage 0 (block.cpp shortens list schedules with it).
#pragma once

#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "isa/ops.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace nesshi::sched::pipe {

using PerFile = std::array<int, isa::kNumRegFiles>;

struct ModelOp {
    int latency = 1;
    std::uint32_t slots = 0;              // bit s: slot s accepts it
    PerFile reads{}, writes{};            // register operands per file
    std::vector<std::pair<int, int>> written; // (file, register)
};

// An op's slots, ports and latency on `m` (repeated reads counted, as the ports count them).
ModelOp model_op(const isa::Machine& m, const isa::Instr& in);

struct ModelEdge {
    int from, to, latency, distance; // t_to >= t_from + latency - distance * II
};

// An induction step whose result is in flight for `latency` > 1 cycles: ops addressing through
// its register (their offset adjusted) must not issue while it flies.
struct ModelFlight {
    int step;
    int latency;
    std::vector<int> users;
};

struct ModelProblem {
    int ii = 1;
    int slot_count = 0;
    PerFile read_ports{}, write_ports{};
    int bubble = 0;                 // the taken-branch bubble, cycles
    std::vector<ModelOp> ops;       // the loop's ops, then the counter decrement (last)
    ModelOp branch;                 // fixed in row II - 1
    bool has_branch = true;         // false: no op is fixed in the last row
    // A straight-line block of II cycles: every op in stage 0, op i issued by cycle latest[i] (so
    // that it lands by the block's end or its final jump's bubble, and before the block's branch
    // as far as that needs); the edges have distance 0.
    bool straight = false;
    std::vector<int> latest;
    std::vector<ModelEdge> edges;
    std::vector<ModelFlight> flights;
};

// A problem with `m`'s slots, register ports and taken-branch bubble, and nothing else yet.
ModelProblem machine_problem(const isa::Machine& m);

// Which back-edge rule the tables keep on a machine with a bubble: none, the rule of a kernel of
// `copies` copies (kernel_landings_ok with its entry nops), or with copies = 0 the rule for any
// number of copies from the write depth up (where it no longer changes).
struct BackEdgeRule {
    bool apply = false;
    int copies = 0;
};

struct ModelSearch {
    enum Outcome { Accepted, Exhausted, Timeout } outcome = Exhausted;
    std::uint64_t nodes = 0;
};

// Row and least stage of each op (the counter last), per table found, until `accept` says true.
using TableAccept = std::function<bool(const std::vector<int>& rows, const std::vector<int>& stages)>;

// Whether propagation at the root alone leaves any table (false: none exists; true: maybe).
bool tables_may_exist(const ModelProblem& p, BackEdgeRule rule);

// Stops with Timeout at the deadline or, when `node_limit` > 0, after that many search nodes (a
// budget that gives the same answer on any host, for what the build makes).
ModelSearch search_tables(const ModelProblem& p, BackEdgeRule rule, std::chrono::steady_clock::time_point deadline,
                          const TableAccept& accept, std::uint64_t node_limit = 0);

} // namespace nesshi::sched::pipe
