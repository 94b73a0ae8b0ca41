// The kernel report (kernel_report.hpp): each metric of kernel_metrics() measured on its
// workload's run from the ISS's label regions, its bounds from sched/bounds.hpp; text and JSON.
#include "machine/kernel_report.hpp"

#include "kbuild/workloads.hpp"

#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "iss/stats.hpp"
#include "sched/bounds.hpp"
#include "kernels/abi.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <utility>

namespace nesshi::machine {

namespace {

using Ranges = std::vector<std::pair<std::uint32_t, std::uint32_t>>; // bundle ranges [first, end)

// Cycles and ops issued in the named regions, and how many times their first bundles issued.
struct Measure {
    double cycles = 0, ops = 0, entries = 0;
    Ranges ranges;
};
Measure measure(const kbuild::KernelRunner& run, const std::vector<std::string>& labels) {
    const iss::Stats st = iss::compute_stats(*run.proc, 0);
    Measure m;
    for (const auto& l : labels) {
        for (const auto& r : st.regions) {
            if (r.label != l) continue;
            m.cycles += static_cast<double>(r.cycles);
            m.ops += static_cast<double>(r.ops);
            m.entries += static_cast<double>(run.proc->counters().exec[r.first]);
            m.ranges.emplace_back(r.first, r.end);
        }
    }
    return m;
}

// Executions of the bundles in `ranges` that load the occupancy byte: the voxel steps.
double loads(const kbuild::KernelRunner& run, const Ranges& ranges) {
    double steps = 0;
    for (auto [a, b] : ranges)
        for (std::uint32_t pc = a; pc < b; ++pc)
            for (const isa::Instr& in : run.prog->bundle_instrs(pc))
                if (in.info().mnemonic == "lbu") steps += static_cast<double>(run.proc->counters().exec[pc]);
    return steps;
}

// The ops of `ranges`, each with its bundle's place along them (the ranges one after another).
std::vector<sched::BodyOp> ops_of(const iss::Program& p, const Ranges& ranges) {
    std::vector<sched::BodyOp> out;
    std::uint32_t cycle = 0;
    for (auto [a, b] : ranges)
        for (std::uint32_t pc = a; pc < b; ++pc, ++cycle)
            for (const isa::Instr& in : p.bundle_instrs(pc))
                if (in.info().kind != isa::Kind::Nop) out.push_back({in, cycle});
    return out;
}

bool branches_to(const isa::Instr& in, std::uint32_t target) {
    const isa::OpInfo& info = in.info();
    for (int k = 0; k < info.num_operands; ++k)
        if (info.operands[static_cast<std::size_t>(k)].kind == isa::OperandKind::Target && in.imm == target) return true;
    return false;
}

// The bundles from `label` falling through to the first one that branches back to it.
Ranges path_from(const iss::Program& p, const std::string& label) {
    const isa::Symbol* s = p.find_symbol(label);
    if (!s || s->kind != isa::SymbolKind::Code) throw std::runtime_error("kernel report: no code label '" + label + "'");
    for (std::uint32_t pc = s->value; pc < p.size(); ++pc)
        for (const isa::Instr& in : p.bundle_instrs(pc))
            if (branches_to(in, s->value)) return {{s->value, pc + 1}};
    throw std::runtime_error("kernel report: no branch back to '" + label + "'");
}

// A row's ResMII and RecMII per iteration over the ops in `ranges`: `iterations` of them, or as
// many as the ops `counts` holds (when given and any).
void set_bounds(KernelRow& r, const iss::Program& p, const Ranges& ranges, double iterations,
                const std::function<bool(const isa::Instr&)>& counts) {
    const auto ops = ops_of(p, ranges);
    std::vector<isa::Instr> instrs;
    for (const sched::BodyOp& o : ops) instrs.push_back(o.instr);
    const sched::ResBound res = sched::res_mii(p.machine(), instrs);
    std::uint32_t bundles = 0;
    for (auto [a, b] : ranges) bundles += b - a;
    const sched::RecBound rec = sched::region_rec_mii(p.machine(), ops, bundles);
    if (counts)
        if (const auto n = std::count_if(instrs.begin(), instrs.end(), counts); n > 0) iterations = static_cast<double>(n);
    r.res_mii = res.cycles / iterations;
    r.rec_mii = rec.cycles / iterations;
    const std::string pass = iterations == 1 ? "" : fmt::format(", / {:.0f} iterations", iterations);
    r.res_binds = res.binds + pass;
    r.rec_binds = rec.binds.empty() ? "" : rec.binds + pass;
}

// The code labels from `first` up to (not including) the next `*_run` or `done*` label after it
// (a hybrid kernel's loops end at done_loops).
std::vector<std::string> run_labels(const iss::Program& p, const std::string& first) {
    const isa::Symbol* s = p.find_symbol(first);
    std::vector<std::pair<std::uint32_t, std::string>> code;
    for (const isa::Symbol& x : p.object().symbols)
        if (x.kind == isa::SymbolKind::Code && x.value >= s->value) code.emplace_back(x.value, x.name);
    std::sort(code.begin(), code.end());
    std::vector<std::string> out;
    for (const auto& [pc, name] : code) {
        const bool next_run = name != first && (name.starts_with("done") || (name.size() > 4 && name.compare(name.size() - 4, 4, "_run") == 0));
        if (next_run) break;
        out.push_back(name);
    }
    return out;
}

// The loop of run `label` in a kernel of per-kind runs: the kernel's loops are in source order, as
// its `*_run` labels are in address order, one loop each (none when the counts differ).
const kbuild::KernelLoop* run_loop(const iss::Program& p, const kbuild::KernelBuild& b, const std::string& label) {
    std::vector<std::pair<std::uint32_t, std::string>> runs;
    for (const isa::Symbol& x : p.object().symbols)
        if (x.kind == isa::SymbolKind::Code && x.name.size() > 4 && x.name.compare(x.name.size() - 4, 4, "_run") == 0)
            runs.emplace_back(x.value, x.name);
    if (runs.size() != b.loops.size()) return nullptr;
    std::sort(runs.begin(), runs.end());
    for (std::size_t k = 0; k < runs.size(); ++k)
        if (runs[k].second == label) return &b.loops[k];
    return nullptr;
}

// What the row's loop, scheduled for the machine, adds to its bounds (`iterations` in `runs` runs
// of one iteration a step or shape):
// - its RecMII as the pipeliner found it in the source: the kernel's code alone does not show the
//   recurrences through the exit test (a load that is not .speculate waits for the last test);
// - the run bound: a software-pipelined run of n iterations issues its last one (n - 1) x II
//   after its first, and that one lasts at least its longest path.
void add_loop_bounds(KernelRow& r, const kbuild::KernelLoop* loop, double iterations, double runs) {
    if (!loop) return;
    if (loop->rec_mii > r.rec_mii) {
        r.rec_mii = loop->rec_mii;
        r.rec_binds = "the loop's recurrences with its exit test (the pipeliner's RecMII)";
    }
    if (runs <= 0 || r.bound() <= 0) return;
    const double n = iterations / runs;
    r.run_bound = ((n - 1) * r.bound() + loop->longest_path) / n;
}

// A row of a per-kind loop kernel (KernelMetric::run).
KernelRow measure_run_row(const KernelMetric& k, const kbuild::WorkloadRun& w, KernelRow r) {
    const kbuild::KernelRunner& run = *w.run;
    const iss::Program& p = *run.prog;
    const std::vector<std::string> labels = run_labels(p, k.run + "_run");
    const Measure ms = measure(run, labels);
    const double per = w.primitives;
    r.cycles = ms.cycles / per;
    r.ops = ms.ops / per;
    r.ilp = ms.cycles > 0 ? ms.ops / ms.cycles : 0;
    r.utilization = r.ilp / static_cast<double>(p.machine().slots.size());
    for (const std::string& l : labels) {
        if (l.size() < 7 || l.compare(l.size() - 7, 7, "_kernel") != 0) continue;
        set_bounds(r, p, path_from(p, l), 1, [](const isa::Instr& in) { // an iteration loads its shape index once
            return in.info().kind == isa::Kind::Load && in.imm == static_cast<std::int32_t>(kernels::abi::get("REC_INDEX"));
        });
    }
    add_loop_bounds(r, run_loop(p, w.build, k.run + "_run"), per, measure(run, {k.run + "_run"}).entries);
    return r;
}

KernelRow measure_row(const KernelMetric& k, const kbuild::WorkloadRun& w) {
    const kbuild::KernelRunner& run = *w.run;
    KernelRow r;
    r.metric = k.metric;
    r.machine = k.machine;
    r.paper = k.paper;
    r.note = k.note;
    if (!k.run.empty() && run.prog->find_symbol(k.run + "_run")) return measure_run_row(k, w, r);
    if (k.per == PerWhat::Rays) { // the whole kernel's processing cycles, ops, ILP and utilisation
        const iss::Stats st = iss::compute_stats(*run.proc, 0);
        r.cycles = static_cast<double>(st.processing_cycles) / w.rays;
        r.ops = static_cast<double>(st.processing_ops) / w.rays;
        r.ilp = st.ilp;
        r.utilization = st.utilisation;
        return r;
    }
    const Measure ms = measure(run, k.labels);
    double per = k.per == PerWhat::Loads       ? loads(run, ms.ranges)
                 : k.per == PerWhat::EntriesOf ? measure(run, k.count_labels).entries
                                               : ms.entries;
    if (per <= 0) per = ms.entries;
    r.cycles = per > 0 ? ms.cycles / per : 0;
    r.ops = per > 0 ? ms.ops / per : 0;
    r.ilp = ms.cycles > 0 ? ms.ops / ms.cycles : 0;
    const isa::Machine& m = run.prog->machine();
    r.utilization = r.ilp / static_cast<double>(m.slots.size());
    if (k.bounds != BoundsFrom::None) {
        Ranges bounded = ms.ranges;
        if (k.bounds == BoundsFrom::Path) bounded = path_from(*run.prog, k.path);
        if (k.bounds == BoundsFrom::Loops) {
            bounded.clear();
            for (const std::string& l : k.labels)
                if (run.prog->find_symbol(l)) {
                    const Ranges loop = path_from(*run.prog, l);
                    bounded.insert(bounded.end(), loop.begin(), loop.end());
                }
        }
        auto occupancy_load = [](const isa::Instr& in) { return in.info().mnemonic == "lbu"; };
        set_bounds(r, *run.prog, bounded, k.iterations, k.iterations_are_loads ? std::function<bool(const isa::Instr&)>(occupancy_load) : nullptr);
    }
    // A loop kernel's steps (BoundsFrom::Loops) measure its kernel only, not its runs' fill and
    // drain: the loop adds its RecMII, not a run bound.
    if (k.bounds == BoundsFrom::Loops && w.build.loops.size() == 1) add_loop_bounds(r, &w.build.loops[0], 0, 0);
    return r;
}

// The runs of the metric being measured: the current machine's two grid runs, or one primitive run.
class Runs {
  public:
    Runs(const kernels::SourceSet& sources, const KernelMachines& machines) : sources_(sources), machines_(machines) {}
    const kbuild::WorkloadRun& get(kbuild::Workload w, const std::string& machine) {
        const isa::Machine& desc = machines_.of(machine).machine();
        if (kbuild::is_grid(w)) {
            if (dda_machine_ != machine) {
                dda_ = kbuild::DdaRuns{};
                dda_ = kbuild::run_dda(sources_, machine, desc);
                dda_machine_ = machine;
            }
            return w == kbuild::Workload::EmptyGrid ? dda_.empty : dda_.sparse;
        }
        if (!prim_.run || prim_workload_ != w || prim_machine_ != machine) {
            prim_ = kbuild::WorkloadRun{};
            prim_ = kbuild::run_intersect(sources_, machine, desc, w);
            prim_workload_ = w;
            prim_machine_ = machine;
        }
        return prim_;
    }

  private:
    const kernels::SourceSet& sources_;
    const KernelMachines& machines_;
    std::string dda_machine_, prim_machine_;
    kbuild::DdaRuns dda_;
    kbuild::Workload prim_workload_ = kbuild::Workload::Triangles;
    kbuild::WorkloadRun prim_;
};

std::string goals_line(const KernelReport& r) {
    std::string line;
    for (const KernelGoal& g : kernel_goals()) {
        std::string values;
        bool met = true;
        for (const std::string& m : g.machines) {
            const KernelRow* row = r.find(g.metric, m);
            if (!row) return {};
            const double v = g.ilp ? row->ilp : row->cycles;
            met = met && (g.ilp ? v >= g.limit : v <= g.limit);
            values += fmt::format("{}{}{:.2f}", values.empty() ? "" : ", ", g.machines.size() > 1 ? m + " " : "", v);
        }
        line += fmt::format("{}{} {} {}: {} ({})", line.empty() ? "" : "; ", g.what, g.ilp ? ">=" : "<=",
                            g.ilp ? fmt::format("{:.1f}", g.limit) : fmt::format("{:.0f}", g.limit), values,
                            met ? "met" : "NOT met");
    }
    return "\ngoals: " + line + "\n";
}

} // namespace

const KernelRow* KernelReport::find(std::string_view metric, std::string_view machine) const {
    for (const KernelRow& r : rows)
        if (r.metric == metric && r.machine == machine) return &r;
    return nullptr;
}

std::string KernelReport::text() const {
    std::string out;
    for (const auto& [role, name] : machines) out += fmt::format("{} rows: machine {}\n", role, name);
    if (!machines.empty()) out += "\n";
    out += fmt::format("{:<13} {:<4} {:>8} {:>7} {:>6} {:>6} {:>6} {:>7} {:>7} {:>6} {:>5}  {}\n", "metric", "mach", "cycles",
                                  "paper", "ops", "ILP", "util", "ResMII", "RecMII", "/bound", "/run", "note");
    for (const KernelRow& r : rows) {
        const std::string paper = r.paper ? fmt::format("{:.0f}", *r.paper) : "-";
        const std::string res = r.res_mii > 0 ? fmt::format("{:.2f}", r.res_mii) : "-";
        const std::string rec = r.rec_mii > 0 ? fmt::format("{:.2f}", r.rec_mii) : "-";
        const std::string over = r.bound() > 0 ? fmt::format("{:.2f}", r.cycles / r.bound()) : "-";
        const std::string over_run = r.run_bound > 0 ? fmt::format("{:.2f}", r.cycles / r.run_bound) : "-";
        out += fmt::format("{:<13} {:<4} {:>8.2f} {:>7} {:>6.1f} {:>6.2f} {:>6.2f} {:>7} {:>7} {:>6} {:>5}  {}\n", r.metric,
                           r.machine, r.cycles, paper, r.ops, r.ilp, r.utilization, res, rec, over, over_run, r.note);
    }
    out += goals_line(*this);
    out += fmt::format("\ncycles: per voxel step / ray / primitive, measured on the ISS (fast engine) from label regions;\n"
                       "paper: Gwun et al. 1993 step counts (3DDDA {:.0f} VLIW / {:.0f} sequential, init {:.0f}, FIFO "
                       "load/store {:.0f},\n"
                       "triangle {:.0f} + {:.0f} load, quadric {:.0f} + {:.0f} load); ILP = ops / cycles in the measured "
                       "code; util = ILP /\n"
                       "issue slots; ResMII, RecMII: lower bounds per step or primitive from the machine description;\n"
                       "/bound: cycles over the larger of the two (1.00 = at the bound); /run (software-pipelined runs of n\n"
                       "shapes): cycles over ((n - 1) x bound + one iteration's longest path) / n, the best a run's fill and\n"
                       "drain allow.\n",
                       kPaper.dda_step_vliw, kPaper.dda_step_seq, kPaper.dda_init, kPaper.fifo_ray, kPaper.triangle,
                       kPaper.triangle_load, kPaper.quadric, kPaper.quadric_load);
    return out;
}

std::string KernelReport::loops_text() const {
    if (loop_reports.empty())
        return "\nno kernel has loops scheduled for its machine (a preset runs its committed kernels)\n";
    std::string out;
    for (const auto& [role, report] : loop_reports)
        out += fmt::format("\n{} kernel: its loops as scheduled for {}\n{}", role,
                           machines.count(role) ? machines.at(role) : role, report);
    return out;
}

std::string KernelReport::json(bool loops) const {
    nlohmann::json j;
    j["kernels"] = nlohmann::json::array();
    if (!machines.empty()) j["machines"] = machines;
    if (loops) j["loop_reports"] = loop_reports;
    for (const KernelRow& r : rows) {
        nlohmann::json e{{"metric", r.metric}, {"machine", r.machine}, {"cycles", r.cycles},   {"ops", r.ops},
                         {"ilp", r.ilp},       {"utilization", r.utilization}, {"res_mii", r.res_mii},
                         {"rec_mii", r.rec_mii}, {"bound", r.bound()},
                         {"run_bound", r.run_bound > 0 ? nlohmann::json(r.run_bound) : nlohmann::json(nullptr)}, {"note", r.note}};
        e["paper"] = r.paper ? nlohmann::json(*r.paper) : nlohmann::json(nullptr);
        j["kernels"].push_back(e);
    }
    return j.dump(2);
}

const kbuild::StageMachine& KernelMachines::of(std::string_view role) const { return role == "os" ? os : role == "ic" ? ic : seq; }

KernelReport kernel_report(const kernels::SourceSet& sources, const KernelMachines& machines) {
    KernelReport r;
    Runs runs(sources, machines);
    for (const KernelMetric& k : kernel_metrics()) {
        const kbuild::WorkloadRun& run = runs.get(k.workload, k.machine);
        if (machines.of(k.machine).reference() != k.machine) {
            const std::string &given = machines.of(k.machine).machine().name, &used = run.run->prog->machine().name;
            r.machines[k.machine] = given == used ? given : fmt::format("{} (the preset {} under another name)", given, used);
        }
        r.rows.push_back(measure_row(k, run));
        if (!run.build.loop_report.empty()) r.loop_reports[k.machine] = run.build.loop_report;
    }
    return r;
}

} // namespace nesshi::machine
