// --exact for counted loops: the tables at one II from the constraint model (exact_model.cpp).
//
// On a machine with a taken-branch bubble a table is only kept when its kernel passes
// kernel_landings_ok for the copies the build gives it (its unroll times its repeats), and the
// search applies that rule too, so that a proof covers what the build would accept: for each
// kernel length c the build can reach (from the fewest copies any unroll gets, upward) the model
// searches the tables that pass the rule for c. From the write depth K on (the passes a write
// stays in flight across) the rule no longer changes with c: one search covers every c >= K.
// When every search is exhausted, no table at this II assembles.
//
// While loops (exit test in the last row, no counter) are not modelled: the caller keeps their
// heuristic schedule.
#include "pipeline_exact.hpp"

#include "exact_model.hpp"
#include "pipeline_registers.hpp"

#include "isa/encoding.hpp"

#include <algorithm>
#include <set>

namespace nesshi::sched::pipe {
namespace {

ModelProblem problem_of(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter) {
    ModelProblem p = machine_problem(m);
    p.ii = ii;
    for (const Node& nd : g.nodes) p.ops.push_back(model_op(m, nd.instr));
    p.ops.push_back(model_op(m, counter));
    p.branch = model_op(m, branch);
    for (const Edge& e : g.ddg.edges) p.edges.push_back({e.from, e.to, e.latency, e.distance});
    for (const Induction& ind : g.inductions) {
        ModelFlight fl{ind.op, g.nodes[static_cast<std::size_t>(ind.op)].latency, {}};
        if (fl.latency <= 1) continue;
        for (std::size_t i = 0; i < g.nodes.size(); ++i)
            if (g.nodes[i].adjusted && g.nodes[i].base == ind.reg) fl.users.push_back(static_cast<int>(i));
        p.flights.push_back(std::move(fl));
    }
    return p;
}

// The back-edge rules whose searches together cover every kernel the build may make at this II.
std::vector<BackEdgeRule> back_edge_rules(const ModelProblem& p) {
    if (p.bubble == 0) return {BackEdgeRule{}};
    // The fewest copies: build's unroll (1 .. kMaxPortUnroll, whatever allocate gives) times the
    // repeats bubble_repeats adds for it. More than kMaxPortUnroll copies never beats that.
    int fewest = kMaxPortUnroll;
    for (int unroll = 1; unroll <= kMaxPortUnroll; ++unroll) {
        const int pass = p.ii * unroll;
        fewest = std::min(fewest, unroll * bubble_repeats(p.bubble, pass, most_repeats(pass)));
    }
    int depth = 0;
    for (const ModelOp& op : p.ops)
        if (std::any_of(op.writes.begin(), op.writes.end(), [](int w) { return w > 0; }))
            depth = std::max(depth, (p.ii - 1 + op.latency - p.bubble) / p.ii);
    std::vector<BackEdgeRule> rules{{true, 0}};
    for (int c = fewest; c < depth; ++c) rules.push_back({true, c});
    return rules;
}

} // namespace

ExactRun exact_schedule(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter,
                        std::chrono::steady_clock::time_point deadline, const std::function<bool(const Schedule&)>& accept,
                        std::uint64_t node_limit) {
    const ModelProblem p = problem_of(g, m, ii, branch, counter);
    const int n = static_cast<int>(g.nodes.size());
    std::set<std::vector<int>> refused; // a table passing several rules is assembled once
    ExactRun run;
    for (const BackEdgeRule& rule : back_edge_rules(p)) {
        const ModelSearch s = search_tables(p, rule, deadline, [&](const std::vector<int>& rows, const std::vector<int>& stages) {
            if (!refused.insert(rows).second) return false;
            ++run.tables;
            Schedule k;
            k.ii = ii;
            for (int i = 0; i < n; ++i) k.time.push_back(rows[static_cast<std::size_t>(i)] + ii * stages[static_cast<std::size_t>(i)]);
            k.normalise();
            k.branch = branch;
            k.counter = counter;
            k.counter_row = rows[static_cast<std::size_t>(n)];
            return accept(k);
        }, node_limit ? node_limit - std::min(node_limit - 1, run.nodes) : 0);
        run.nodes += s.nodes;
        if (s.outcome == ModelSearch::Accepted) {
            run.outcome = ExactOutcome::Accepted;
            return run;
        }
        if (s.outcome == ModelSearch::Timeout) {
            run.outcome = ExactOutcome::Timeout;
            return run;
        }
    }
    run.outcome = ExactOutcome::Exhausted;
    return run;
}

} // namespace nesshi::sched::pipe
