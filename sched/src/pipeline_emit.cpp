#include "pipeline_emit.hpp"

#include "text.hpp"

#include "assembler/assembler.hpp"
#include "assembler/op_text.hpp"
#include "base/error.hpp"
#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cctype>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <regex>
#include <set>
#include <stdexcept>
#include <tuple>

namespace nesshi::sched::pipe {

namespace {

// ---- emission -----------------------------------------------------------------------------------

// An iteration index in the emitted code: `base` is 0 (prologue, absolute) or the trip count N
// (epilogue, relative); the kernel's instances are steady.
struct Iter {
    bool from_end = false;
    int offset = 0;
};

class Emitter {
  public:
    Emitter(const Region& r, const Graph& g, const Schedule& s, const Allocation& a, const isa::Machine& m)
        : r_(r), g_(g), s_(s), a_(a), m_(m), stages_(s.stages()) {}
    int stages() const { return stages_; }

    // Memory op `op` on an induction register (nullopt for any other op): the induction op,
    // whether `op` follows it in the body, and m = floor((t_op - t_ind - latency) / II) + 1, the
    // later iterations' increments that have landed when `op` issues.
    struct InductionView {
        const Induction* ind;
        int after, m;
    };
    std::optional<InductionView> induction_view(int op) const {
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        if (!nd.adjusted) return std::nullopt;
        const Induction& ind = *g_.induction_of(nd.base);
        const int ta = s_.time[static_cast<std::size_t>(ind.op)], la = g_.nodes[static_cast<std::size_t>(ind.op)].latency;
        const int diff = s_.time[static_cast<std::size_t>(op)] - ta - la;
        const int m = (diff >= 0 ? diff / s_.ii : -((-diff + s_.ii - 1) / s_.ii)) + 1; // floor + 1
        return InductionView{&ind, op > ind.op ? 1 : 0, m};
    }

    // Offset change of memory op `op` of iteration `it` on an induction register: the increments
    // the op should see minus those that have landed when it issues.
    std::int64_t delta(int op, std::optional<Iter> it) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        const Induction& ind = *view->ind;
        const int after = view->after, m = view->m;
        std::int64_t seen_minus_i; // (increments landed) - i
        if (!it) seen_minus_i = m;  // steady state
        else if (!it->from_end) seen_minus_i = std::max(it->offset + m, 0) - it->offset;
        else seen_minus_i = std::min(m, -it->offset); // i = N + offset, at most N increments
        return ind.step * (after - seen_minus_i);
    }

    // Offset change of memory op `op` in an iteration run alone at the schedule's times: its
    // own induction step has landed when the op issues after it (m >= 1), no other.
    std::int64_t delta_alone(int op) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        return view->ind->step * (view->after - (view->m >= 1 ? 1 : 0));
    }

    std::string instance(int op, int iteration_mod, std::optional<Iter> it) const {
        std::vector<std::string> vreg;
        for (std::size_t v = 0; v < r_.virtuals.size(); ++v) {
            const int k = a_.copies[v];
            vreg.push_back(a_.regs[v][static_cast<std::size_t>(((iteration_mod % k) + k) % k)]);
        }
        return op_text(r_.ops[static_cast<std::size_t>(op)], r_, vreg, delta(op, it));
    }

    static std::string bundle(const std::vector<std::string>& ops) {
        if (ops.empty()) return "        nop\n";
        if (ops.size() == 1) return "        " + ops[0] + "\n";
        std::string s = "        { ";
        for (std::size_t k = 0; k < ops.size(); ++k) s += (k ? " ; " : "") + ops[k];
        return s + " }\n";
    }

    // `trip_min` (.trip, 0: none) drops the paths no run can take; `shape` receives the bundles
    // of each part (whole_run_cycles). Every kernel copy counts one iteration and tests for the
    // last: a run of any length leaves the kernel after its last iteration's copy, into the
    // epilogue whose registers that copy's rotation left, so no iteration runs outside the
    // pipeline but those of trips too short for it.
    std::string code(const std::string& trip, const std::string& uid, int trip_min = 0, CountedShape* shape = nullptr) const {
        const int ii = s_.ii, p = stages_ - 1, u = a_.unroll, copies = u * a_.groups;
        const std::string rk = reg_name(isa::RegFile::Int, a_.counter);
        const int alu_lat = static_cast<int>(m_.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
        auto nops = [&](int n) {
            std::string s;
            for (int k = 0; k < n; ++k) s += "        nop\n";
            return s;
        };
        const int lag = lag_passes(alu_lat);
        CountedShape sh;
        sh.alu_latency = std::max(1, alu_lat);
        sh.penalty = static_cast<int>(m_.branch_penalty);
        sh.prologue_passes = p, sh.unroll = u, sh.groups = a_.groups, sh.ii = ii, sh.entry_nops = a_.entry_nops;
        sh.min_pipelined = p + 1 + lag; // at least one kernel copy, and the counter's lag
        sh.guard = trip_min < 1;
        sh.short_path = trip_min < sh.min_pipelined;
        std::string o;
        // Sequential copy: trip counts below the pipeline's minimum.
        if (sh.guard) o += fmt::format("        beqz {}, {}_done\n", trip, uid);
        if (sh.short_path) {
            o += fmt::format("        slti {}, {}, {}\n", rk, trip, sh.min_pipelined) + nops(alu_lat - 1);
            o += fmt::format("        beqz {}, {}_pipe\n", rk, uid);
            o += fmt::format("{}_seq:\n", uid);
            std::vector<std::string> vreg0;
            for (std::size_t v = 0; v < r_.virtuals.size(); ++v) vreg0.push_back(a_.regs[v][0]);
            // One iteration alone: each op after the previous one's result has landed, or, with
            // .trip (the default's code stays as it was), the modulo schedule's own placement of
            // one iteration when that is shorter: each bundle a subset of a kernel row (slots,
            // ports and landings hold), every dependence within the iteration met by the schedule,
            // and every result landed before the next iteration starts.
            int serial = 0, first = s_.time[0], flat = 0;
            for (std::size_t k = 0; k < r_.ops.size(); ++k) {
                serial += std::max(1, g_.nodes[k].latency);
                first = std::min(first, s_.time[k]);
                flat = std::max(flat, s_.time[k] + std::max(1, g_.nodes[k].latency));
            }
            flat -= first;
            if (trip_min > 0 && flat < serial) {
                for (int t = first; t < first + flat; ++t) {
                    std::vector<std::string> ops;
                    for (std::size_t k = 0; k < r_.ops.size(); ++k)
                        if (s_.time[k] == t) ops.push_back(op_text(r_.ops[k], r_, vreg0, delta_alone(static_cast<int>(k))));
                    o += bundle(ops);
                }
                sh.body = flat;
            } else {
                for (std::size_t k = 0; k < r_.ops.size(); ++k) {
                    o += "        " + op_text(r_.ops[k], r_, vreg0, 0) + "\n";
                    o += nops(g_.nodes[k].latency - 1);
                }
                sh.body = serial;
            }
            o += fmt::format("        addi {}, {}, -1\n", trip, trip) + nops(alu_lat - 1);
            o += fmt::format("        bnez {}, {}_seq\n", trip, uid);
            o += fmt::format("        jmp {}_done\n", uid);
        }
        // Pipelined: N >= min_pipelined; the counter holds the iterations the kernel starts.
        o += fmt::format("{}_pipe:\n", uid);
        o += fmt::format("        addi {}, {}, {}\n", rk, trip, -(p + lag)) + nops(alu_lat - 1);
        sh.setup = sh.alu_latency;
        o += fmt::format("# prologue: {} pass{} of {} cycles\n", p, p == 1 ? "" : "es", ii);
        for (int pass = 0; pass < p; ++pass)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii;
                    if (t % ii == row && st <= pass) ops.push_back(instance(static_cast<int>(op), pass - st, Iter{false, pass - st}));
                }
                o += bundle(ops);
            }
        // The epilogue after a kernel copy of rotation v (copy c leaves rotation c mod u): v = u - 1
        // falls out of the kernel's last copy; the others are reached from their copies' exit tests.
        const auto exit_label = [&](int v) { return fmt::format("{}_exit{}", uid, v); };
        if (copies == 1)
            o += fmt::format("# kernel: 1 copy of II = {} cycles, {} stage{}\n", ii, stages_, stages_ == 1 ? "" : "s");
        else
            o += fmt::format("# kernel: {} copies of II = {} cycles, {} stage{} (registers rotating every {}); each copy "
                             "counts an iteration and leaves after the last\n",
                             copies, ii, stages_, stages_ == 1 ? "" : "s", u);
        for (int k = 0; k < a_.entry_nops; ++k) o += "        nop\n";
        o += fmt::format("{}_kernel:\n", uid);
        for (int c = 0; c < copies; ++c)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii;
                    if (t % ii == row) ops.push_back(instance(static_cast<int>(op), p + c - st, std::nullopt));
                }
                if (row == s_.counter_row) ops.push_back(fmt::format("addi {}, {}, -1", rk, rk));
                if (row == ii - 1)
                    ops.push_back(c == copies - 1 ? fmt::format("bnez {}, {}_kernel", rk, uid)
                                                  : fmt::format("beqz {}, {}", rk, exit_label(c % u)));
                o += bundle(ops);
            }
        // Results still in flight land before the code after the loop runs: nops until the last
        // write of the kernel's final pass and of the epilogue lands (cycles from the epilogue's
        // first bundle), not the longest latency. The trip register ends at 0 as in the
        // sequential meaning.
        int last = (s_.counter_row - ii) + static_cast<int>(m_.latency_of(s_.counter.info()));
        for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
            const int t = s_.time[op], st = t / ii, row = t % ii, lat = g_.nodes[op].latency;
            last = std::max(last, row - ii + lat);                          // the kernel's final pass
            if (st > 0) last = std::max(last, (st - 1) * ii + row + lat); // its last epilogue pass
        }
        for (int k = 0; k < u; ++k) {
            const int v = (u - 1 + k) % u; // the fall-through rotation first
            if (copies > 1) o += exit_label(v) + ":\n";
            o += fmt::format("# epilogue: {} pass{}\n", p, p == 1 ? "" : "es");
            std::string epilogue;
            for (int q = 0; q < p; ++q)
                for (int row = 0; row < ii; ++row) {
                    std::vector<std::string> ops;
                    for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                        const int t = s_.time[op], st = t / ii;
                        if (t % ii == row && st >= q + 1)
                            ops.push_back(instance(static_cast<int>(op), p + v + 1 + q - st, Iter{true, q - st}));
                    }
                    epilogue += bundle(ops);
                }
            while (epilogue.size() >= 12 && epilogue.compare(epilogue.size() - 12, 12, "        nop\n") == 0)
                epilogue.resize(epilogue.size() - 12); // trailing empty bundles: the drain below covers them
            o += epilogue;
            const int tail_bundles = static_cast<int>(std::count(epilogue.begin(), epilogue.end(), '\n')); // a bundle a line
            const int drain = std::max(0, last - tail_bundles - 1);
            o += nops(drain);
            o += fmt::format("        li {}, 0\n", trip);
            sh.tail = tail_bundles + drain + 1;
            if (k + 1 < u) o += fmt::format("        jmp {}_done\n", uid);
        }
        o += fmt::format("{}_done:\n", uid);
        if (shape) *shape = sh;
        return o;
    }

    // ---- while loops: exits from the prologue and from every kernel copy ----

    // The branch's stage, and the increments of induction `ind` the loop has issued by the time
    // the exit of iteration e is taken, beyond the e + a of the sequential meaning (a: the step
    // comes before the exit test in the source). Later iterations' steps run ahead of the exit.
    int exit_stage() const { return s_.time[static_cast<std::size_t>(r_.exit_op)] / s_.ii; }
    int ahead(const Induction& ind) const {
        const int a = ind.op < r_.exit_op ? 1 : 0;
        return std::max(0, exit_stage() - s_.time[static_cast<std::size_t>(ind.op)] / s_.ii + 1 - a);
    }

    // Offset change of memory op `op` of iteration i (absolute: i counts from the first
    // iteration, else relative to the kernel); `exiting`: after the exit of that iteration, when
    // no step beyond those already issued and the sequential ones is issued.
    std::int64_t delta_while(int op, int i, bool absolute, std::optional<int> exiting) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        const Induction& ind = *view->ind;
        const int after = view->after, m = view->m;
        std::int64_t seen = i + m;                                                         // increments landed
        if (absolute) seen = std::max<std::int64_t>(seen, 0);
        if (exiting) seen = std::min<std::int64_t>(seen, *exiting + (ind.op < r_.exit_op ? 1 : 0) + ahead(ind));
        return ind.step * (after - (seen - i));
    }

    // The registers of iteration i's virtuals (a carried one's copy rotates like any other).
    std::vector<std::string> regs_of(int i) const {
        std::vector<std::string> vreg;
        for (std::size_t v = 0; v < r_.virtuals.size(); ++v) {
            const int k = a_.copies[v];
            vreg.push_back(a_.regs[v][static_cast<std::size_t>(((i % k) + k) % k)]);
        }
        return vreg;
    }
    std::string reg_of(const std::string& name, int i) const {
        return regs_of(i)[static_cast<std::size_t>(r_.virtual_index.at(name))];
    }

    std::string instance_at(int op, int i, std::int64_t delta) const {
        const std::vector<std::string> prev = regs_of(i - 1);
        return op_text(r_.ops[static_cast<std::size_t>(op)], r_, regs_of(i), delta, &prev, op);
    }

    // A register copy in one op: `addi d, s, 0` or `fmov d, s`, and its latency.
    std::pair<std::string, int> move(const std::string& to, const std::string& from) const {
        const bool f = from[0] == 'f';
        return {f ? fmt::format("fmov {}, {}", to, from) : fmt::format("addi {}, {}, 0", to, from),
                static_cast<int>(m_.latency[static_cast<std::size_t>(f ? isa::OpClass::FAdd : isa::OpClass::Alu)])};
    }
    // The operation of a move's text, for the slot and port checks.
    static isa::Instr move_instr(const std::string& text) {
        const assembler::OperationText op = assembler::split_operation(text);
        const auto d = assembler::register_named(op.operands.at(0).text), src = assembler::register_named(op.operands.at(1).text);
        isa::Instr in;
        in.opcode = src.value().first == isa::RegFile::Float ? isa::opcode("fmov") : isa::opcode("addi");
        in.rd = static_cast<std::uint8_t>(d.value().second);
        in.rs1 = static_cast<std::uint8_t>(src.value().second);
        return in;
    }
    // The moves packed into as few bundles as the machine takes (isa::assign_slots and
    // isa::bundle_fits decide), then nops until they have landed.
    std::string moves_text(const std::vector<std::pair<std::string, int>>& ms) const {
        std::string o;
        int lat = 1;
        std::vector<std::vector<isa::Instr>> ops; // per bundle: each move goes to the first that takes it
        std::vector<std::vector<std::string>> texts;
        for (const auto& [text, l] : ms) {
            lat = std::max(lat, l);
            const isa::Instr in = move_instr(text);
            std::size_t b = 0;
            for (; b < ops.size(); ++b) {
                std::vector<isa::Instr> trial = ops[b];
                trial.push_back(in);
                std::vector<int> pinned(trial.size(), -1);
                if (isa::assign_slots(m_, trial, pinned) && isa::bundle_fits(m_, trial)) break;
            }
            if (b == ops.size()) ops.emplace_back(), texts.emplace_back();
            ops[b].push_back(in);
            texts[b].push_back(text);
        }
        for (const auto& t : texts) o += bundle(t);
        for (int k = 1; k < lat && !ms.empty(); ++k) o += "        nop\n";
        return o;
    }

    // The exit path's first bundles: carried and live-out values of the exiting iteration e
    // (landed, by the graph's edges) to their registers.
    std::vector<std::pair<std::string, int>> exit_moves(int e) const {
        std::vector<std::pair<std::string, int>> ms;
        for (const auto& [name, c] : r_.carry) {
            const int def = r_.virtuals[static_cast<std::size_t>(r_.virtual_index.at(name))].def;
            ms.push_back(move(c.out, reg_of(name, def < r_.exit_op ? e : e - 1)));
            if (!c.old.empty()) ms.push_back(move(c.old, reg_of(name, e - 1)));
        }
        for (const auto& [name, reg] : r_.liveout) ms.push_back(move(reg, reg_of(name, e)));
        return ms;
    }

    // The exit test of iteration i, branching to `label`; inverted, it is the kernel's back edge.
    std::string exit_branch(int i, const std::string& label, bool invert) const {
        static const std::map<std::string, std::string> inverse = {{"beqz", "bnez"}, {"bnez", "beqz"}, {"beq", "bne"},
                                                                   {"bne", "beq"},   {"blt", "bge"},   {"bge", "blt"},
                                                                   {"bltu", "bgeu"}, {"bgeu", "bltu"}};
        SrcOp b = r_.ops[static_cast<std::size_t>(r_.exit_op)];
        if (invert) b.mnemonic = inverse.at(b.mnemonic);
        b.operands.back() = label;
        const std::vector<std::string> prev = regs_of(i - 1);
        return op_text(b, r_, regs_of(i), 0, &prev, r_.exit_op);
    }

    // Writes per register file landing in each cycle after the exit test of pass `pass` (cycle 0)
    // from the ops issued before it: the passes back to the prologue's first (`absolute`: an exit
    // in the prologue), or in the kernel the copies of this pass and, a taken-branch bubble
    // earlier or not (the prologue before), all earlier ones.
    using Landings = std::vector<std::array<std::uint32_t, isa::kNumRegFiles>>;
    Landings in_flight(int pass, bool absolute, int horizon) const {
        Landings at(static_cast<std::size_t>(horizon));
        const int b = static_cast<int>(m_.branch_penalty), p = stages_ - 1, copy = absolute ? pass : pass - p;
        for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
            const Node& nd = g_.nodes[i];
            const int st = s_.time[i] / s_.ii;
            for (int j = 0;; ++j) { // j passes back
                const int issue = s_.time[i] % s_.ii - (s_.ii - 1) - j * s_.ii;
                if (issue + nd.latency <= 0 || (absolute && (j > pass || st > pass - j))) break;
                // Before this pass's first copy: the previous kernel pass, a bubble earlier, or the
                // prologue (its pass p - (j - copy), holding stages up to that; entered after
                // entry nops as long as the bubble, or straight).
                const bool before_kernel = !absolute && j > copy;
                const bool from_prologue = before_kernel && st <= p - (j - copy);
                // Shifts by which the write lands earlier: none within this pass; before it, the
                // back edge's bubble, and none from a prologue entered straight.
                const bool straight = !before_kernel || (from_prologue && a_.entry_nops == 0 && b > 0);
                for (const int shift : {before_kernel ? b : 0, 0}) {
                    if (const int land = issue - shift + nd.latency; land > 0 && land < horizon)
                        add_writes(at[static_cast<std::size_t>(land)], nd.instr, 1);
                    if (!straight || !before_kernel) break;
                }
            }
        }
        return at;
    }
    static void add_writes(std::array<std::uint32_t, isa::kNumRegFiles>& at, const isa::Instr& in, int sign) {
        for (const isa::RegOperand& o : isa::register_operands(in))
            if (o.write) at[static_cast<std::size_t>(o.file)] += static_cast<std::uint32_t>(sign);
    }
    bool room(const std::array<std::uint32_t, isa::kNumRegFiles>& at) const {
        for (int f = 0; f < isa::kNumRegFiles; ++f)
            if (at[static_cast<std::size_t>(f)] > m_.regs[static_cast<std::size_t>(f)].write_ports) return false;
        return true;
    }

    // What runs after the exit of iteration e is taken at the end of pass P: the older iterations
    // complete, the exiting one runs what precedes its exit test in the source, younger ones are
    // dropped (they have issued no side effect); then in-flight results land and inductions step
    // back by what ran ahead. The exit moves go to the first bundles whose slots and whose
    // landing cycle's write ports (with the results still in flight) take them, and the
    // completing iterations start when they have landed and no write of theirs meets one in
    // flight on a port.
    std::string exit_path(int pass, int e, bool absolute, bool taken) const {
        const int ii = s_.ii;
        std::vector<std::vector<std::string>> rows;
        std::vector<std::vector<const isa::Instr*>> row_instrs;
        for (int q = pass + 1; q <= e + stages_ - 1; ++q)
            for (int row = 0; row < ii; ++row) {
                rows.emplace_back();
                row_instrs.emplace_back();
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = q - st;
                    if (t % ii != row || static_cast<int>(op) == r_.exit_op || i > e || (absolute && i < 0)) continue;
                    if (i == e && static_cast<int>(op) > r_.exit_op) continue;
                    rows.back().push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, absolute, e)));
                    row_instrs.back().push_back(&g_.nodes[op].instr);
                }
            }
        while (!rows.empty() && rows.back().empty()) rows.pop_back(), row_instrs.pop_back();
        int longest = 1;
        for (const Node& nd : g_.nodes) longest = std::max(longest, nd.latency);
        const auto ms = exit_moves(e);
        const int horizon = 2 * (longest + static_cast<int>(m_.branch_penalty) + ii) + static_cast<int>(ms.size()) * 16 + 64;
        // The exit path's first bundle issues in cycle 1, or after the bubble of a taken exit.
        const int first = 1 + (taken ? static_cast<int>(m_.branch_penalty) : 0);
        Landings at = in_flight(pass, absolute, horizon);
        std::vector<std::vector<isa::Instr>> move_ops;
        std::vector<std::vector<std::string>> move_texts;
        int lat = 1;
        for (const auto& [text, l] : ms) {
            lat = std::max(lat, l);
            const isa::Instr in = move_instr(text);
            for (std::size_t b = 0;; ++b) {
                if (b == move_ops.size()) move_ops.emplace_back(), move_texts.emplace_back();
                std::vector<isa::Instr> trial = move_ops[b];
                trial.push_back(in);
                std::vector<int> pinned(trial.size(), -1);
                const std::size_t land = static_cast<std::size_t>(first) + b + static_cast<std::size_t>(l);
                auto cycle = at[std::min(land, at.size() - 1)];
                add_writes(cycle, in, 1);
                if (isa::assign_slots(m_, trial, pinned) && isa::bundle_fits(m_, trial) && room(cycle)) {
                    move_ops[b].push_back(in);
                    move_texts[b].push_back(text);
                    if (land < at.size()) add_writes(at[land], in, 1);
                    break;
                }
            }
        }
        std::string o;
        for (const auto& t : move_texts) o += bundle(t);
        // The completing iterations from cycle `start`: after the moves have landed, and later
        // while a write of theirs would meet one in flight on a port.
        int start = first + static_cast<int>(move_ops.size()) + (ms.empty() ? 0 : lat - 1);
        for (int tries = 0; tries < horizon / 2; ++tries, ++start) {
            Landings trial = at;
            bool fits = true;
            for (std::size_t k = 0; fits && k < row_instrs.size(); ++k)
                for (const isa::Instr* in : row_instrs[k]) {
                    const std::size_t land = static_cast<std::size_t>(start) + k + m_.latency_of(in->info());
                    if (land >= trial.size()) continue;
                    add_writes(trial[land], *in, 1);
                    fits = fits && room(trial[land]);
                }
            if (fits) break;
        }
        if (!rows.empty())
            for (int k = first + static_cast<int>(move_ops.size()); k < start; ++k) o += "        nop\n";
        for (const auto& row : rows) o += bundle(row);
        // The code after the loop may read or write any register, so it starts once every write
        // has landed (those in flight at the exit, the moves', the completing iterations'), not
        // after the longest latency of all. The inductions step back once the integer writes have
        // landed (their own steps among them) and the completing iterations have read them.
        int cycle = rows.empty() ? first + static_cast<int>(move_ops.size()) : start + static_cast<int>(rows.size());
        int last = cycle, int_last = cycle;
        auto lands = [&](int land, bool to_int) {
            last = std::max(last, land);
            if (to_int) int_last = std::max(int_last, land);
        };
        constexpr auto kInt = static_cast<std::size_t>(isa::RegFile::Int);
        for (std::size_t c = 0; c < at.size(); ++c)
            if (std::any_of(at[c].begin(), at[c].end(), [](std::uint32_t w) { return w > 0; })) lands(static_cast<int>(c), at[c][kInt] > 0);
        for (std::size_t k = 0; k < row_instrs.size(); ++k)
            for (const isa::Instr* in : row_instrs[k])
                lands(start + static_cast<int>(k) + static_cast<int>(m_.latency_of(in->info())), writes_to(*in, static_cast<int>(kInt)) > 0);
        const int alu_lat = static_cast<int>(m_.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
        bool stepped = false;
        for (const Induction& ind : g_.inductions)
            if (const int x = ahead(ind); x > 0) {
                for (; !stepped && cycle < int_last; ++cycle) o += "        nop\n";
                stepped = true;
                o += fmt::format("        addi {0}, {0}, {1}\n", reg_name(isa::RegFile::Int, ind.reg), -ind.step * x);
                last = std::max(last, cycle + alu_lat);
                ++cycle;
            }
        for (; cycle < last; ++cycle) o += "        nop\n";
        return o;
    }

    std::string while_code(const std::string& uid) const {
        const int ii = s_.ii, p = stages_ - 1, u = a_.unroll, sb = exit_stage();
        std::string o;
        struct Exit {
            std::string label;
            int pass, e;
            bool absolute;
        };
        std::vector<Exit> exits;
        std::vector<std::pair<std::string, int>> in; // carried values into the copy iteration 0 reads
        for (const auto& [name, c] : r_.carry) in.push_back(move(reg_of(name, -1), c.in));
        o += moves_text(in);
        o += fmt::format("# prologue: {} pass{} of {} cycles (exit test from pass {})\n", p, p == 1 ? "" : "es", ii, sb);
        for (int pass = 0; pass < p; ++pass)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = pass - st;
                    if (t % ii != row || st > pass) continue;
                    if (static_cast<int>(op) == r_.exit_op) {
                        exits.push_back({fmt::format("{}_exit_p{}", uid, pass), pass, i, true});
                        ops.push_back(exit_branch(i, exits.back().label, false));
                    } else {
                        ops.push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, true, std::nullopt)));
                    }
                }
                o += bundle(ops);
            }
        o += fmt::format("# kernel: {} cop{} of II = {} cycles, {} stage{}; each copy ends in the exit test\n", u,
                         u == 1 ? "y" : "ies", ii, stages_, stages_ == 1 ? "" : "s");
        for (int k = 0; k < a_.entry_nops; ++k) o += "        nop\n";
        o += fmt::format("{}_kernel:\n", uid);
        std::vector<Exit> kernel_exits;
        for (int c = 0; c < u; ++c)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = p + c - st;
                    if (t % ii != row) continue;
                    if (static_cast<int>(op) == r_.exit_op) {
                        const bool last = c == u - 1;
                        kernel_exits.push_back({fmt::format("{}_exit_k{}", uid, c), p + c, i, false});
                        ops.push_back(exit_branch(i, last ? uid + "_kernel" : kernel_exits.back().label, last));
                    } else {
                        ops.push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, false, std::nullopt)));
                    }
                }
                o += bundle(ops);
            }
        // The last copy's exit falls through; the other exits branch to their own paths.
        std::rotate(kernel_exits.begin(), kernel_exits.end() - 1, kernel_exits.end());
        exits.insert(exits.begin(), kernel_exits.begin(), kernel_exits.end());
        for (std::size_t k = 0; k < exits.size(); ++k) {
            const Exit& x = exits[k];
            if (x.absolute)
                o += fmt::format("# exit of iteration {} at the end of prologue pass {}\n", x.e, x.pass);
            else
                o += fmt::format("# exit from kernel copy {}: its iteration in stage {} leaves{}\n", x.pass - p, sb,
                                 stages_ - 1 == sb ? "" : fmt::format(", the {} older complete", stages_ - 1 - sb));
            if (k > 0) o += x.label + ":\n";
            o += exit_path(x.pass, x.e, x.absolute, k > 0);
            if (k + 1 < exits.size()) o += fmt::format("        jmp {}_done\n", uid);
        }
        o += fmt::format("{}_done:\n", uid);
        return o;
    }

    // How many kernel passes the counter's decrement lands late for the branch that reads it.
    int lag_passes(int alu_lat) const {
        const int land = s_.counter_row + alu_lat; // cycle (from its pass's start) it lands
        return land <= s_.ii - 1 ? 0 : (land - (s_.ii - 1) + s_.ii - 1) / s_.ii;
    }

  private:
    const Region& r_;
    const Graph& g_;
    const Schedule& s_;
    const Allocation& a_;
    const isa::Machine& m_;
    int stages_ = 1;
};

} // namespace

Emitted emit_region(const Region& r, const Graph& g, const Schedule& s, const Allocation& a, const isa::Machine& m,
                    const std::string& uid, int trip_min, CountedShape* shape) {
    const Emitter em(r, g, s, a, m);
    return {r.is_while ? em.while_code(uid) : em.code(r.trip, uid, trip_min, shape), em.stages()};
}

} // namespace nesshi::sched::pipe
