#include "pipeline_report.hpp"

#include "isa/bundle_check.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace nesshi::sched::pipe {

// Each row of the II as data: its ops with the slots they issue in (isa::assign_slots, as the
// emitter bundles them), mnemonic, class and stage; the loop control (counter, branch) in no stage.
// The report's table and the picture are both drawn from it.
std::vector<TableRow> schedule_rows(const Graph& g, const Region& r, const Schedule& s, const isa::Machine& m) {
    std::vector<TableRow> rows(static_cast<std::size_t>(s.ii));
    for (int row = 0; row < s.ii; ++row) {
        std::vector<isa::Instr> ops;
        std::vector<std::pair<std::string, int>> names; // mnemonic, stage
        for (std::size_t k = 0; k < g.nodes.size(); ++k)
            if (s.time[k] % s.ii == row) ops.push_back(g.nodes[k].instr), names.push_back({r.ops[k].mnemonic, s.time[k] / s.ii});
        if (s.loop_control && row == s.counter_row) ops.push_back(s.counter), names.push_back({"addi", -1});
        if (s.loop_control && row == s.ii - 1) ops.push_back(s.branch), names.push_back({"bnez", -1});
        std::vector<int> pinned(ops.size(), -1);
        isa::assign_slots(m, ops, pinned);
        for (std::size_t k = 0; k < ops.size(); ++k)
            rows[static_cast<std::size_t>(row)].ops.push_back(
                {m.slots[ops[k].slot].name, names[k].first,
                 std::string(isa::kOpClassNames[static_cast<std::size_t>(ops[k].info().cls)]), names[k].second});
    }
    return rows;
}

std::string mrt_text(const std::vector<TableRow>& rows) {
    std::string o = "#   modulo reservation table (cycle mod II: operations [stage])\n";
    for (std::size_t row = 0; row < rows.size(); ++row) {
        std::string cells;
        for (const TableRow::Op& op : rows[row].ops)
            cells += op.stage >= 0 ? fmt::format(" {}:{}[{}]", op.slot, op.op, op.stage)
                                   : fmt::format(" {}:{}({})", op.slot, op.op, op.op == "bnez" ? "loop" : "counter");
        o += fmt::format("#   {:>3} |{}\n", row, cells);
    }
    return o;
}

// The schedule as LoopReport draws it: each row of the II with its ops (slot, mnemonic, class,
// stage; loop control in no stage) and the register ports they use (reads at issue, writes where
// they land, mod II), and each virtual register's lifetime from its definition.
LoopReport schedule_picture(const Graph& g, const Region& r, const Schedule& s, std::vector<TableRow> rows,
                            const std::vector<int>& lifetime, const isa::Machine& m, std::string_view filename,
                            const std::string& verdict) {
    LoopReport p;
    p.label = r.is_while ? "software-pipelined while" : "software-pipelined";
    p.source = fmt::format("{}:{}", filename, r.begin + 1);
    p.machine = m.name;
    p.ii = s.ii;
    p.verdict = verdict;
    for (const isa::SlotDesc& d : m.slots) p.slots.push_back(d.name);
    for (int f = 0; f < 2; ++f) {
        p.read_ports[f] = m.regs[static_cast<std::size_t>(f)].read_ports;
        p.write_ports[f] = m.regs[static_cast<std::size_t>(f)].write_ports;
        p.file_size[f] = m.regs[static_cast<std::size_t>(f)].count;
    }
    p.table = std::move(rows);
    auto land = [&](const isa::Instr& in, int issue) { // reads at issue, writes where they land, mod II
        for (const isa::RegOperand& o : isa::register_operands(in))
            ++(o.write ? p.table[static_cast<std::size_t>((issue + static_cast<int>(m.latency_of(in.info()))) % s.ii)].writes
                       : p.table[static_cast<std::size_t>(issue % s.ii)].reads)[static_cast<int>(o.file)];
    };
    for (std::size_t k = 0; k < g.nodes.size(); ++k) land(g.nodes[k].instr, s.time[k]);
    if (s.loop_control) {
        land(s.counter, s.counter_row);
        land(s.branch, s.ii - 1);
    }
    p.ops = static_cast<int>(g.nodes.size()) + (s.loop_control ? 2 : 0);
    std::vector<int> live[2] = {std::vector<int>(static_cast<std::size_t>(s.ii), 0), std::vector<int>(static_cast<std::size_t>(s.ii), 0)};
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int born = r.virtuals[v].def >= 0 ? s.time[static_cast<std::size_t>(r.virtuals[v].def)] : 0;
        const int f = static_cast<int>(r.virtuals[v].file);
        p.lifetimes.push_back({r.virtuals[v].name, lifetime[v], born, f});
        for (int c = 0; c < std::max(1, lifetime[v]); ++c) ++live[f][static_cast<std::size_t>((born + c) % s.ii)];
    }
    for (int f = 0; f < 2; ++f) p.max_live[f] = *std::max_element(live[f].begin(), live[f].end());
    return p;
}

// The report lines of a while loop: how far iterations run ahead of the exit test, what they may
// do there, and the exit paths.
std::string while_report(const Graph& g, const Region& r, const Schedule& s, const PipelineResult& res) {
    const int tb = s.time[static_cast<std::size_t>(r.exit_op)];
    std::string o = fmt::format("#   exit test in stage {}: {} later iteration{} start{} before it is decided, with no side effect "
                                "(stores, FIFO words, loads not .speculate, physical registers but inductions wait for it)\n",
                                res.exit_stage, res.exit_stage, res.exit_stage == 1 ? "" : "s", res.exit_stage == 1 ? "s" : "");
    std::map<std::pair<bool, std::string>, int> load_ahead; // base (physical first) -> iterations past the exit its loads may run
    for (std::size_t k = 0; k < g.nodes.size(); ++k)
        if (g.nodes[k].instr.info().kind == isa::Kind::Load && g.nodes[k].speculative) {
            int ahead = tb >= s.time[k] ? (tb - s.time[k]) / s.ii : 0;
            if (static_cast<int>(k) > r.exit_op) ahead += 1; // the exiting iteration's own load after its test
            const SrcOp& op = r.ops[k];
            const std::string& mem = op.operands.back(); // `off(base)`: the name as written
            const std::string base = mem.substr(mem.find('(') + 1, mem.rfind(')') - mem.find('(') - 1);
            int& a = load_ahead[{base[0] == '%', base}];
            a = std::max(a, ahead);
        }
    for (const auto& [base, n] : load_ahead)
        o += fmt::format("#   speculative loads on {}: up to {} iteration{} past the exit (those addresses must be mapped)\n",
                         base.second, n, n == 1 ? "" : "s");
    const int prologue_exits = std::max(0, res.stages - 1 - res.exit_stage);
    o += fmt::format("#   exit paths: {} from the prologue, {} from the kernel (one per copy); no trip count, no "
                     "sequential fallback\n", prologue_exits, res.unroll);
    return o;
}

} // namespace nesshi::sched::pipe
