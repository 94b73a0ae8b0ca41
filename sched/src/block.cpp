// Critical-path list scheduling of straight-line blocks (see block.hpp).
#include "sched/block.hpp"

#include "sched/ddg.hpp"

#include "exact_model.hpp"
#include "text.hpp"

#include "assembler/assembler.hpp"
#include "assembler/op_text.hpp"
#include "base/error.hpp"
#include "isa/object.hpp"
#include "isa/ops.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cctype>
#include <deque>
#include <exception>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

namespace nesshi::sched {

namespace {

// One op as the scheduler sees it (its dependences are the block's Ddg, ddg.hpp).
struct BlockOp {
    isa::OpClass cls;
    int latency = 1;
    std::optional<std::pair<int, int>> dst;  // (file, register)
    std::vector<std::pair<int, int>> srcs;   // every register read, repeats included
    bool barrier = false;                    // branch or halt: waits for every earlier op
    bool branch = false;
};

BlockOp describe(const isa::Machine& m, const isa::Instr& in) {
    const isa::OpInfo& info = in.info();
    BlockOp b;
    b.cls = info.cls;
    b.latency = static_cast<int>(m.latency_of(info));
    for (const isa::RegOperand& o : isa::register_operands(in)) {
        const std::pair<int, int> reg{static_cast<int>(o.file), o.reg};
        if (o.write) b.dst = reg;
        else b.srcs.push_back(reg);
    }
    b.branch = info.cls == isa::OpClass::Branch;
    b.barrier = b.branch || (info.cls == isa::OpClass::Misc && info.kind != isa::Kind::Nop);
    return b;
}

struct Pred {
    int op;
    int after; // this op issues at least `after` cycles after `op` (negative: it may issue before)
};

// Each op's predecessors in the block's dependence graph. `grace`: cycles a result may land
// after the block's end (its final jump's bubble, when no code of the block or of its target
// issues).
std::vector<std::vector<Pred>> dependences(const isa::Machine& m, std::span<const isa::Instr> instrs, int grace) {
    const Ddg g = block_ddg(m, instrs, grace);
    std::vector<std::vector<Pred>> preds(static_cast<std::size_t>(g.nodes));
    for (const Dep& e : g.edges) preds[static_cast<std::size_t>(e.to)].push_back({e.from, e.latency});
    return preds;
}

// Ops no float unit (a slot that accepts fadd) accepts: the integer units are the scarce ones.
bool integer_only(const isa::Machine& m, isa::OpClass c) {
    if (m.slots.size() <= 1) return false;
    return std::none_of(m.slots.begin(), m.slots.end(),
                        [&](const isa::SlotDesc& s) { return s.accepts(c) && s.accepts(isa::OpClass::FAdd); });
}

// Highest first: the longest path to the block's end, raised for integer-only ops by how many
// of them remain from here on.
std::vector<int> priorities(const isa::Machine& m, std::span<const BlockOp> ops, const std::vector<std::vector<Pred>>& preds) {
    const int n = static_cast<int>(ops.size());
    std::vector<std::vector<Pred>> succs(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j)
        for (const Pred& p : preds[static_cast<std::size_t>(j)]) succs[static_cast<std::size_t>(p.op)].push_back({j, p.after});
    std::vector<int> height(static_cast<std::size_t>(n)), prio(static_cast<std::size_t>(n));
    for (int i = n - 1; i >= 0; --i) {
        int h = ops[static_cast<std::size_t>(i)].latency;
        for (const Pred& s : succs[static_cast<std::size_t>(i)]) h = std::max(h, s.after + height[static_cast<std::size_t>(s.op)]);
        height[static_cast<std::size_t>(i)] = h;
    }
    int remaining = 0;
    for (int i = n - 1; i >= 0; --i) {
        int p = height[static_cast<std::size_t>(i)];
        if (integer_only(m, ops[static_cast<std::size_t>(i)].cls)) p = std::max(p, ++remaining + 1);
        for (const Pred& s : succs[static_cast<std::size_t>(i)]) p = std::max(p, s.after + prio[static_cast<std::size_t>(s.op)]);
        prio[static_cast<std::size_t>(i)] = p;
    }
    return prio;
}

bool next_permutation_prefix(std::vector<int>& pick, int slots) {
    // The next k-permutation of 0..slots-1 in lexicographic order (pick holds k distinct values).
    const int k = static_cast<int>(pick.size());
    for (int pos = k - 1; pos >= 0; --pos) {
        for (int v = pick[static_cast<std::size_t>(pos)] + 1; v < slots; ++v) {
            if (std::find(pick.begin(), pick.begin() + pos, v) != pick.begin() + pos) continue;
            pick[static_cast<std::size_t>(pos)] = v;
            // the rest: the smallest unused values in order
            int fill = 0;
            for (int q = pos + 1; q < k; ++q) {
                while (std::find(pick.begin(), pick.begin() + q, fill) != pick.begin() + q) ++fill;
                pick[static_cast<std::size_t>(q)] = fill++;
            }
            return true;
        }
    }
    return false;
}

} // namespace

std::vector<int> ordered_slots(const isa::Machine& m, std::span<const isa::Instr> ops) {
    const int slots = static_cast<int>(m.slots.size());
    const int k = static_cast<int>(ops.size());
    if (k > slots) return {};
    std::vector<std::optional<std::pair<int, int>>> dst(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i)
        for (const isa::RegOperand& o : isa::register_operands(ops[static_cast<std::size_t>(i)]))
            if (o.write) dst[static_cast<std::size_t>(i)] = std::pair{static_cast<int>(o.file), o.reg};
    std::vector<int> pick(static_cast<std::size_t>(k));
    std::iota(pick.begin(), pick.end(), 0);
    do {
        bool ok = true;
        int last_fifo = -1;
        for (int i = 0; i < k && ok; ++i) {
            const isa::OpInfo& info = ops[static_cast<std::size_t>(i)].info();
            const int s = pick[static_cast<std::size_t>(i)];
            ok = m.slots[static_cast<std::size_t>(s)].accepts(info.cls);
            if (ok && info.cls == isa::OpClass::Fifo) {
                ok = s > last_fifo;
                last_fifo = s;
            }
            // Two writes of one register in one bundle land in slot order (the later one in
            // program order lands later, so it takes the higher slot).
            for (int e = 0; e < i && ok; ++e)
                ok = !(dst[static_cast<std::size_t>(i)] && dst[static_cast<std::size_t>(i)] == dst[static_cast<std::size_t>(e)]) ||
                     pick[static_cast<std::size_t>(e)] < s;
        }
        if (ok) return pick;
    } while (next_permutation_prefix(pick, slots));
    return {};
}

namespace {

// The block's ops as the schedulers see them, and their dependences. A block that ends in an
// unconditional jump (j, jr) lets its results land during the jump's taken-branch bubble: the
// target's first bundle issues branch_penalty cycles after the block's end, and no bundle issues
// in between (the assembler's hazard check charges the jump 1 + branch_penalty cycles too).
struct Described {
    std::vector<BlockOp> ops;
    std::vector<std::vector<Pred>> preds;
    int grace = 0; // cycles after the block's end by which every result lands
};

Described describe_block(const isa::Machine& m, std::span<const isa::Instr> instrs) {
    Described d;
    for (const isa::Instr& in : instrs) d.ops.push_back(describe(m, in));
    if (!instrs.empty()) {
        const isa::Kind last = instrs.back().info().kind;
        if (last == isa::Kind::Jump || last == isa::Kind::JumpReg) d.grace = static_cast<int>(m.branch_penalty);
    }
    d.preds = dependences(m, instrs, d.grace);
    return d;
}

std::vector<std::vector<int>> list_schedule(const isa::Machine& m, std::span<const isa::Instr> instrs, const Described& d) {
    const int n = static_cast<int>(instrs.size());
    const std::vector<BlockOp>& ops = d.ops;
    const auto& preds = d.preds;
    for (int j = 0; j + 1 < n; ++j)
        if (ops[static_cast<std::size_t>(j)].barrier)
            throw std::invalid_argument(fmt::format("list_schedule: '{}' is op {} of {}; a block's control operation comes last",
                                                    instrs[static_cast<std::size_t>(j)].info().mnemonic, j + 1, n));
    const std::vector<int> prio = priorities(m, ops, preds);
    // Every op is ready by the sum of all latencies plus one cycle each; a cycle past that means
    // an op no bundle can take (an op no slot accepts on this machine), not a slow schedule.
    int horizon = 1;
    for (const BlockOp& op : ops) horizon += op.latency + 1;

    std::vector<int> cycle_of(static_cast<std::size_t>(n), -1);
    std::vector<std::vector<int>> bundles;
    std::vector<std::array<std::uint32_t, isa::kNumRegFiles>> reads;
    std::map<int, std::array<std::uint32_t, isa::kNumRegFiles>> writes; // per landing cycle
    int done = 0, c = 0;
    bool progress = true;
    while (done < n) {
        while (static_cast<int>(bundles.size()) <= c) {
            bundles.emplace_back();
            reads.push_back({});
        }
        if (!progress) { // nothing more fits in this cycle
            if (++c > horizon)
                throw std::invalid_argument(fmt::format("list_schedule: {} of {} ops placed after {} cycles; the rest fit no "
                                                        "bundle of machine '{}'", done, n, c, m.name));
            progress = true;
            continue;
        }
        progress = false;
        std::vector<int> ready;
        for (int j = 0; j < n; ++j) {
            if (cycle_of[static_cast<std::size_t>(j)] >= 0) continue;
            const bool met = std::all_of(preds[static_cast<std::size_t>(j)].begin(), preds[static_cast<std::size_t>(j)].end(), [&](const Pred& p) {
                const int at = cycle_of[static_cast<std::size_t>(p.op)];
                return at >= 0 && at + p.after <= c;
            });
            if (met && !(ops[static_cast<std::size_t>(j)].branch && done != n - 1)) ready.push_back(j);
        }
        std::stable_sort(ready.begin(), ready.end(),
                         [&](int a, int b) { return prio[static_cast<std::size_t>(a)] > prio[static_cast<std::size_t>(b)]; });
        for (int j : ready) {
            const BlockOp& op = ops[static_cast<std::size_t>(j)];
            std::vector<int> trial = bundles[static_cast<std::size_t>(c)];
            trial.insert(std::upper_bound(trial.begin(), trial.end(), j), j);
            std::vector<isa::Instr> trial_ops;
            for (int i : trial) trial_ops.push_back(instrs[static_cast<std::size_t>(i)]);
            if (ordered_slots(m, trial_ops).empty()) continue;
            auto r = reads[static_cast<std::size_t>(c)];
            for (const auto& s : op.srcs) ++r[static_cast<std::size_t>(s.first)];
            bool ports = true;
            for (int f = 0; f < isa::kNumRegFiles; ++f)
                ports = ports && r[static_cast<std::size_t>(f)] <= m.regs[static_cast<std::size_t>(f)].read_ports;
            if (!ports) continue;
            if (op.dst) {
                const auto& w = writes[c + op.latency];
                const auto f = static_cast<std::size_t>(op.dst->first);
                if (w[f] + 1 > m.regs[f].write_ports) continue;
            }
            bundles[static_cast<std::size_t>(c)] = trial;
            reads[static_cast<std::size_t>(c)] = r;
            if (op.dst) ++writes[c + op.latency][static_cast<std::size_t>(op.dst->first)];
            cycle_of[static_cast<std::size_t>(j)] = c;
            ++done;
            progress = true;
        }
    }
    while (!bundles.empty() && bundles.back().empty()) bundles.pop_back();
    // A block that falls through ends when its last result lands, as its sequential meaning does
    // (a final branch or halt already waits for them all).
    if (n > 0 && !ops.back().barrier) {
        std::size_t lands = 0;
        for (int j = 0; j < n; ++j)
            lands = std::max(lands, static_cast<std::size_t>(cycle_of[static_cast<std::size_t>(j)] + ops[static_cast<std::size_t>(j)].latency));
        while (bundles.size() < lands) bundles.emplace_back();
    }
    return bundles;
}

} // namespace

std::vector<std::vector<int>> list_schedule(const isa::Machine& m, std::span<const isa::Instr> instrs) {
    return list_schedule(m, instrs, describe_block(m, instrs));
}

namespace {

// Block op i of the model: its issue cycle at most latest[i] in a block of `length` bundles. Its
// result lands by the end (and the grace after it), and the block's final control op (the
// model's pinned branch) waits for its dependences.
std::vector<int> latest_issue(const Described& d, int length) {
    const std::vector<BlockOp>& ops = d.ops;
    const auto& preds = d.preds;
    const bool barrier = !ops.empty() && ops.back().barrier;
    const std::size_t n = ops.size() - (barrier ? 1 : 0);
    std::vector<int> latest(n);
    for (std::size_t i = 0; i < n; ++i) latest[i] = length - ops[i].latency + d.grace;
    if (barrier)
        for (const Pred& p : preds.back()) {
            int& l = latest[static_cast<std::size_t>(p.op)];
            l = std::min(l, length - 1 - p.after);
        }
    return latest;
}

} // namespace

BlockSchedule block_schedule(const isa::Machine& m, std::span<const isa::Instr> instrs, std::uint64_t node_budget) {
    const Described d = describe_block(m, instrs);
    BlockSchedule out;
    out.bundles = list_schedule(m, instrs, d);
    out.list_bundles = static_cast<int>(out.bundles.size());
    if (node_budget == 0 || instrs.size() < 2) return out;
    std::vector<std::vector<int>>& best = out.bundles;
    const std::vector<BlockOp>& ops = d.ops;
    const auto& preds = d.preds;
    const bool barrier = ops.back().barrier;
    const int n = static_cast<int>(ops.size()) - (barrier ? 1 : 0); // the model's ops
    // Nothing is shorter than the longest dependence path to the last landing (or the last
    // issue, where the final jump's bubble leaves time to land).
    std::vector<int> asap(ops.size(), 0);
    int shortest = 1;
    for (std::size_t j = 0; j < ops.size(); ++j) {
        for (const Pred& p : preds[j]) asap[j] = std::max(asap[j], asap[static_cast<std::size_t>(p.op)] + std::max(p.after, 0));
        shortest = std::max(shortest, asap[j] + (ops[j].barrier ? 1 : std::max(ops[j].latency - d.grace, 1)));
    }
    pipe::ModelProblem p = pipe::machine_problem(m); // its bubble is unused: a block has no back edge
    for (int i = 0; i < n; ++i) p.ops.push_back(pipe::model_op(m, instrs[static_cast<std::size_t>(i)]));
    p.has_branch = barrier;
    if (barrier) p.branch = pipe::model_op(m, instrs.back());
    p.straight = true;
    // As list_schedule places them: never before an op they depend on (the assembler refuses a
    // read of a register while a write of it is in flight, even one landing after the read).
    for (int j = 0; j < n; ++j)
        for (const Pred& d : preds[static_cast<std::size_t>(j)]) p.edges.push_back({d.op, j, std::max(d.after, 0), 0});
    auto at_length = [&](int length) {
        p.ii = length;
        p.latest = latest_issue(d, length);
        return p;
    };
    // The fewest bundles the model's propagation alone does not refute: no block is shorter (a
    // block of L bundles is one of L + 1 too, so refutations are monotone).
    int lo = shortest, hi = static_cast<int>(best.size());
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (pipe::tables_may_exist(at_length(mid), {})) hi = mid;
        else lo = mid + 1;
    }
    // Then shorter blocks than the best so far, from one bundle fewer, while the search finds one.
    int length = static_cast<int>(best.size()) - 1;
    while (length >= lo) {
        std::vector<std::vector<int>> found;
        int found_length = 0;
        const pipe::ModelSearch s = pipe::search_tables(
            at_length(length), {}, std::chrono::steady_clock::time_point::max(),
            [&](const std::vector<int>& rows, const std::vector<int>&) {
                std::vector<std::vector<int>> bundles(static_cast<std::size_t>(length));
                for (int i = 0; i < n; ++i) bundles[static_cast<std::size_t>(rows[static_cast<std::size_t>(i)])].push_back(i);
                if (barrier) bundles.back().push_back(n);
                // The model's slot rule does not see FIFO words' or one register's writes' slot order.
                for (const auto& b : bundles) {
                    if (b.size() < 2) continue;
                    std::vector<isa::Instr> in;
                    for (int i : b) in.push_back(instrs[static_cast<std::size_t>(i)]);
                    if (ordered_slots(m, in).empty()) return false;
                }
                // A block without a branch ends at its last landing, which may come sooner.
                found_length = barrier ? length : 0;
                for (int i = 0; i < n && !barrier; ++i)
                    found_length = std::max(found_length, rows[static_cast<std::size_t>(i)] + ops[static_cast<std::size_t>(i)].latency);
                bundles.resize(static_cast<std::size_t>(found_length));
                found = std::move(bundles);
                return true;
            },
            node_budget);
        if (s.outcome == pipe::ModelSearch::Exhausted) out.fewest = length + 1;
        if (s.outcome != pipe::ModelSearch::Accepted) break;
        best = std::move(found);
        length = found_length - 1;
    }
    out.fewest = std::max(out.fewest, lo);
    return out;
}

namespace {

struct Block {
    int begin_line = 0; // 1-based, of `#pack begin`
    std::vector<std::string> texts;
    std::vector<int> lines; // of each op in the sequential text (1-based)
};

// The assembler's diagnostics of the sequential text, with its line numbers turned back into the
// file's (the sequential text has padding nops the file does not have).
std::string source_lines(const std::string& diagnostics, std::string_view filename, const std::vector<int>& line_of) {
    std::string out;
    const std::string prefix = std::string(filename) + ":";
    std::size_t pos = 0;
    while (pos < diagnostics.size()) {
        const std::size_t hit = diagnostics.find(prefix, pos);
        if (hit == std::string::npos) break;
        std::size_t end = hit + prefix.size();
        int line = 0;
        while (end < diagnostics.size() && std::isdigit(static_cast<unsigned char>(diagnostics[end])))
            line = line * 10 + (diagnostics[end++] - '0');
        out.append(diagnostics, pos, hit + prefix.size() - pos);
        if (line > 0 && static_cast<std::size_t>(line) < line_of.size()) out += std::to_string(line_of[static_cast<std::size_t>(line)]);
        else out.append(diagnostics, hit + prefix.size(), end - hit - prefix.size());
        pos = end;
    }
    out.append(diagnostics, pos, std::string::npos);
    return out;
}

bool marker(std::string_view line, std::string_view word) {
    return trim(line).starts_with(word);
}

// The pools of `#pack virtual rA-rB` / `fA-fB` lines, per register file, in register order.
using Pools = std::array<std::vector<int>, isa::kNumRegFiles>;

void declare_pool(Pools& pools, std::string_view line, std::string_view filename, int ln) {
    const std::string range = strip_comment(trim(line).substr(std::string_view("#pack virtual").size()));
    const std::size_t dash = range.find('-');
    const auto lo = dash == std::string::npos ? std::nullopt : assembler::register_named(trim(range.substr(0, dash)));
    const auto hi = dash == std::string::npos ? std::nullopt : assembler::register_named(trim(range.substr(dash + 1)));
    if (!lo || !hi || lo->first != hi->first || lo->second > hi->second)
        throw base::Error(base::SourceLoc(filename, ln),
                          fmt::format("'#pack virtual' takes one register range of one file, e.g. f71-f127; not '{}'", range));
    const int a = lo->second, b = hi->second;
    std::vector<int>& pool = pools[static_cast<std::size_t>(lo->first)];
    pool.clear();
    for (int r = a; r <= b; ++r) pool.push_back(r);
}

// A block's ops with their virtual registers (%name, live inside the block) on the pools'
// registers: linear scan in program order. An op frees the registers of the values it reads for
// the last time before its result takes one; a freed register goes to the back of the free list,
// a result takes the front (so a register is reused as late as the range allows). A value never read keeps
// its register to the block's end. The pools' registers belong to the tool: the block must not
// name them.
std::vector<std::string> allocate_virtuals(const std::vector<std::string>& ops, const std::vector<int>& lines,
                                           const Pools& pools, std::string_view filename) {
    struct Ref {
        std::string name;
        std::size_t pos, len; // in the op text
        isa::RegFile file;
        bool dest;
    };
    auto fail = [&](std::size_t i, const std::string& msg) -> void {
        throw base::Error(base::SourceLoc(filename, lines[i]), msg);
    };
    std::vector<std::vector<Ref>> refs(ops.size());
    std::map<std::string, std::size_t> last; // name -> its last op
    std::map<std::string, isa::RegFile> file_of;
    for (std::size_t i = 0; i < ops.size(); ++i) {
        const std::string& op = ops[i];
        if (op.find('%') == std::string::npos) continue;
        const assembler::OperationText split = assembler::split_operation(op);
        const std::string& mnemonic = split.mnemonic;
        const auto opc = isa::find_opcode(mnemonic);
        if (!opc) fail(i, fmt::format("'{}': virtual registers go in the operands of a machine operation", mnemonic));
        const isa::OpInfo& info = isa::kOps[*opc];
        std::vector<std::string> operands;
        for (const assembler::OperandText& o : split.operands) operands.push_back(o.text);
        if (operands.size() != info.num_operands) fail(i, fmt::format("'{}' takes {} operands", mnemonic, info.num_operands));
        for (std::size_t k = 0; k < operands.size(); ++k) {
            const std::size_t start = split.operands[k].col;
            const std::size_t pct = operands[k].find('%');
            if (pct == std::string::npos) continue;
            std::size_t e = pct + 1;
            while (e < operands[k].size() && (std::isalnum(static_cast<unsigned char>(operands[k][e])) || operands[k][e] == '_')) ++e;
            const std::string name = operands[k].substr(pct, e - pct);
            const isa::Operand& desc = info.operands[k];
            isa::RegFile f = isa::RegFile::Int; // (fail throws)
            if (desc.kind == isa::OperandKind::FloatReg) f = isa::RegFile::Float;
            else if (desc.kind == isa::OperandKind::IntReg || (desc.kind == isa::OperandKind::Mem && operands[k].find('(') < pct))
                f = isa::RegFile::Int;
            else fail(i, fmt::format("{}: a virtual register where '{}' takes no register", name, mnemonic));
            if (pools[static_cast<std::size_t>(f)].empty())
                fail(i, fmt::format("{}: no '#pack virtual' range of {} registers before this block", name,
                                    f == isa::RegFile::Int ? "integer" : "float"));
            const auto [it, fresh] = file_of.emplace(name, f);
            if (!fresh && it->second != f) fail(i, fmt::format("{} is used both as an integer and as a float register", name));
            refs[i].push_back({name, start + pct, e - pct, f, desc.is_dest});
            last[name] = i;
        }
    }
    std::array<std::deque<int>, isa::kNumRegFiles> free;
    for (std::size_t f = 0; f < free.size(); ++f) free[f].assign(pools[f].begin(), pools[f].end());
    std::map<std::string, int> reg; // live virtual -> register
    std::vector<std::string> out;
    for (std::size_t i = 0; i < ops.size(); ++i) {
        std::map<std::string, int> here;
        for (const Ref& r : refs[i]) {
            if (r.dest) continue;
            const auto it = reg.find(r.name);
            if (it == reg.end())
                fail(i, fmt::format("{} is read before this block writes it (a virtual register lives inside one block)", r.name));
            here[r.name] = it->second;
        }
        for (const Ref& r : refs[i]) { // in operand order, once each
            if (r.dest || last[r.name] != i || !reg.count(r.name)) continue;
            free[static_cast<std::size_t>(r.file)].push_back(reg[r.name]);
            reg.erase(r.name);
        }
        for (const Ref& r : refs[i]) {
            if (!r.dest) continue;
            if (!reg.count(r.name)) {
                std::deque<int>& pool = free[static_cast<std::size_t>(r.file)];
                if (pool.empty()) fail(i, fmt::format("{}: every register of the '#pack virtual' range is live here", r.name));
                reg[r.name] = pool.front();
                pool.pop_front();
            }
            here[r.name] = reg[r.name];
        }
        std::string text = ops[i];
        for (auto r = refs[i].rbegin(); r != refs[i].rend(); ++r)
            text.replace(r->pos, r->len, fmt::format("{}{}", r->file == isa::RegFile::Int ? 'r' : 'f', here[r->name]));
        out.push_back(std::move(text));
    }
    return out;
}

} // namespace

namespace {

// Each block's schedule, on as many threads as the host has (blocks are independent and each
// search is deterministic, so the code is the same on any host); a block's exception is
// rethrown, the first block's first.
std::vector<BlockSchedule> schedule_blocks(const isa::Machine& m, const std::vector<std::vector<isa::Instr>>& blocks) {
    std::vector<BlockSchedule> out(blocks.size());
    std::vector<std::exception_ptr> failed(blocks.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t k = next++; k < blocks.size(); k = next++) {
            try {
                out[k] = block_schedule(m, blocks[k], kBlockSearchNodes);
            } catch (...) {
                failed[k] = std::current_exception();
            }
        }
    };
    const std::size_t threads = std::min<std::size_t>(blocks.size(), std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
    return out;
}

PackResult pack_expanded(std::string_view text, std::string_view filename, const isa::Machine& m,
                         const assembler::AsmOptions& opts) {
    const std::vector<std::string> lines = split_lines(text);
    const std::vector<bool> keep = machine_lines(lines, filename, m);
    // The sequential meaning: each block op alone in its bundle, followed by enough nops for its
    // result to land, so the file assembles and every op decodes exactly.
    std::vector<Block> blocks;
    std::string sequential;
    int out_line = 0;
    std::vector<int> source_line{0}; // of each line of `sequential` (1-based), for diagnostics
    std::size_t current = 0;         // the source line being copied
    auto emit = [&](const std::string& s) {
        sequential += s;
        sequential += '\n';
        ++out_line;
        source_line.push_back(static_cast<int>(current + 1));
    };
    Block* open = nullptr;
    Pools pools;
    std::vector<std::string> texts; // of the open block, as written
    std::vector<int> text_lines;    // their source lines (1-based)
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string& s = lines[i];
        current = i;
        if (!keep[i]) continue;
        if (marker(s, "#pack virtual")) {
            if (open) throw base::Error(base::SourceLoc(filename, static_cast<int>(i + 1)), "'#pack virtual' inside a block");
            declare_pool(pools, s, filename, static_cast<int>(i + 1));
            emit("");
            continue;
        }
        if (marker(s, "#pack begin")) {
            if (open) throw base::Error(base::SourceLoc(filename, static_cast<int>(i + 1)), "'#pack begin' inside a block");
            blocks.push_back({static_cast<int>(i + 1), {}, {}});
            open = &blocks.back();
            texts.clear();
            text_lines.clear();
            emit("");
            continue;
        }
        if (marker(s, "#pack end")) {
            if (!open) throw base::Error(base::SourceLoc(filename, static_cast<int>(i + 1)), "'#pack end' without '#pack begin'");
            // Each op alone, with nops until it lands; its diagnostics point at its own line.
            const std::vector<std::string> ops = allocate_virtuals(texts, text_lines, pools, filename);
            for (std::size_t k = 0; k < ops.size(); ++k) {
                current = static_cast<std::size_t>(text_lines[k] - 1);
                open->texts.push_back(ops[k]);
                emit("        " + ops[k]);
                open->lines.push_back(out_line);
                for (std::uint32_t n = 1; n < m.max_latency(); ++n) emit("        nop");
            }
            current = i;
            open = nullptr;
            emit("");
            continue;
        }
        if (!open) {
            emit(s);
            continue;
        }
        const std::string op = strip_comment(s);
        if (op.empty()) continue;
        texts.push_back(op);
        text_lines.push_back(static_cast<int>(i + 1));
    }
    if (open) throw base::Error(base::SourceLoc(filename, open->begin_line), "'#pack begin' is never closed by '#pack end'");

    const assembler::AsmResult res = assembler::assemble_string(sequential, filename, m, opts);
    if (!res.ok)
        throw base::Error(base::SourceLoc(filename),
                          fmt::format("does not assemble for machine '{}' even with its blocks written sequentially (the "
                                      "code outside the blocks is scheduled by hand):\n{}", m.name,
                                      source_lines(res.diagnostics, filename, source_line)));
    const std::vector<std::vector<isa::Instr>> decoded = isa::decode_bundles(res.object);
    std::map<int, isa::Instr> by_line; // sequential line -> its op (main file only)
    for (std::size_t b = 0; b < decoded.size() && b < res.object.lines.size(); ++b) {
        const isa::LineEntry& le = res.object.lines[b];
        if (le.file < res.object.files.size() && res.object.files[le.file] == filename && decoded[b].size() == 1)
            by_line[static_cast<int>(le.line)] = decoded[b][0];
    }

    std::vector<std::vector<isa::Instr>> block_instrs;
    for (const Block& b : blocks) {
        std::vector<isa::Instr>& instrs = block_instrs.emplace_back();
        for (int l : b.lines) {
            const auto it = by_line.find(l);
            if (it == by_line.end())
                throw base::Error(base::SourceLoc(filename, b.begin_line), "an op of this block did not assemble to one operation");
            instrs.push_back(it->second);
        }
        for (std::size_t k = 0; k + 1 < instrs.size(); ++k)
            if (describe(m, instrs[k]).barrier)
                throw base::Error(base::SourceLoc(filename, source_line[static_cast<std::size_t>(b.lines[k])]),
                                  fmt::format("'{}' before the end of a '#pack' block: a block is straight-line code, "
                                              "its one control operation (a branch or halt) is its last",
                                              instrs[k].info().mnemonic));
    }
    const std::vector<BlockSchedule> schedules = schedule_blocks(m, block_instrs);

    PackResult out;
    std::size_t next_block = 0;
    bool in_block = false;
    std::vector<std::string> result;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string& s = lines[i];
        if (!keep[i] || marker(s, "#pack virtual")) continue;
        if (marker(s, "#pack begin")) {
            in_block = true;
            continue;
        }
        if (marker(s, "#pack end")) {
            in_block = false;
            const Block& b = blocks[next_block];
            const std::vector<isa::Instr>& instrs = block_instrs[next_block];
            const BlockSchedule& scheduled = schedules[next_block++];
            const auto& bundles = scheduled.bundles;
            for (const auto& bundle : bundles) {
                if (bundle.empty()) {
                    result.push_back("        nop");
                    continue;
                }
                std::vector<isa::Instr> ops;
                bool ordered = false; // FIFO words, or two writes of one register
                std::set<std::pair<int, int>> written;
                for (int i : bundle) {
                    ops.push_back(instrs[static_cast<std::size_t>(i)]);
                    const BlockOp d = describe(m, ops.back());
                    const isa::Kind k = ops.back().info().kind;
                    ordered = ordered || k == isa::Kind::Recv || k == isa::Kind::Send || (d.dst && !written.insert(*d.dst).second);
                }
                std::vector<std::string> texts;
                if (ordered && bundle.size() > 1) { // pin the slots: the assembler takes slot order as program order
                    const std::vector<int> slots = ordered_slots(m, ops);
                    std::vector<std::size_t> order(bundle.size());
                    std::iota(order.begin(), order.end(), 0);
                    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t c) { return slots[a] < slots[c]; });
                    for (std::size_t k : order)
                        texts.push_back(fmt::format("{}: {}", m.slots[static_cast<std::size_t>(slots[k])].name,
                                                    b.texts[static_cast<std::size_t>(bundle[k])]));
                } else {
                    for (int i : bundle) texts.push_back(b.texts[static_cast<std::size_t>(i)]);
                }
                std::string line = "        { ";
                for (std::size_t k = 0; k < texts.size(); ++k) line += (k ? " ; " : "") + texts[k];
                result.push_back(line + " }");
            }
            out.blocks.push_back({b.begin_line, static_cast<int>(instrs.size()), static_cast<int>(bundles.size()),
                                  scheduled.list_bundles, scheduled.fewest, scheduled.shortest()});
            continue;
        }
        if (!in_block) result.push_back(s);
    }
    for (const std::string& s : result) out.text += s + '\n';
    return out;
}

} // namespace

PackResult pack_source(std::string_view text, std::string_view filename, const isa::Machine& m,
                       const assembler::AsmOptions& opts) {
    try {
        PackResult r = pack_expanded(expand_copies(text, filename), filename, m, opts);
        if (text.find("#copy") == std::string_view::npos) return r;
        const CopiedLines copied(text, filename); // a copy's block is reported at the line it copies
        for (BlockStats& b : r.blocks)
            if (const auto o = copied(b.line)) b.line = o->line;
        return r;
    } catch (const base::Error& e) { // a line of a #copy is named by the line it copies
        const CopiedLines copied(text, filename);
        std::string message = copied.named(e.message());
        base::SourceLoc loc = e.loc();
        if (const auto o = copied(loc.line)) {
            loc.line = o->line;
            message += o->note();
        }
        if (message == e.message() && loc.line == e.loc().line) throw;
        throw base::Error(loc, message);
    }
}

std::vector<bool> machine_lines(const std::vector<std::string>& lines, std::string_view filename, const isa::Machine& m) {
    std::vector<bool> keep(lines.size(), true);
    enum { Outside, If, Else } state = Outside;
    bool match = false;
    int opened = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string t = trim(lines[i]);
        const int ln = static_cast<int>(i + 1);
        if (marker(t, "#if machine")) {
            if (state != Outside) throw base::Error(base::SourceLoc(filename, ln), "'#if machine' inside another (sections do not nest)");
            const std::string name(trim(t.substr(std::string_view("#if machine").size())));
            if (name.empty() || !isa::is_preset(name))
                throw base::Error(base::SourceLoc(filename, ln), fmt::format("'#if machine' names no preset machine ('{}')", name));
            match = isa::load_machine(name).same_as(m);
            state = If;
            opened = ln;
            keep[i] = false;
        } else if (t == "#else" && state != Outside) {
            if (state == Else) throw base::Error(base::SourceLoc(filename, ln), "a second '#else' in one '#if machine' section");
            state = Else;
            keep[i] = false;
        } else if (t == "#endif" && state != Outside) {
            state = Outside;
            keep[i] = false;
        } else if (state != Outside) {
            keep[i] = state == If ? match : !match;
        }
    }
    if (state != Outside) throw base::Error(base::SourceLoc(filename, opened), "'#if machine' is never closed by '#endif'");
    return keep;
}

std::string machine_sections(std::string_view text, std::string_view filename, const isa::Machine& m) {
    const std::vector<std::string> lines = split_lines(expand_copies(text, filename));
    const std::vector<bool> keep = machine_lines(lines, filename, m);
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i) out += (keep[i] ? lines[i] : std::string()) + '\n';
    return out;
}

} // namespace nesshi::sched
