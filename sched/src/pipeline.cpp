// Software pipelining from linear assembly (see pipeline.hpp), the driver: parse the region
// (pipeline_region), write and assemble its sequential meaning to get exact operations
// (pipeline_sequential), build the dependence graph (pipeline_graph), modulo-schedule it II by II
// (pipeline_search, pipeline_exact, pipeline_solver), allocate registers (pipeline_registers) and
// emit prologue, kernel and epilogue as assembly text (pipeline_emit); choose among schedules,
// verify, and report (pipeline_report draws the table and the picture).
#include "sched/pipeline.hpp"

#include "pipeline_emit.hpp"
#include "pipeline_exact.hpp"
#include "pipeline_report.hpp"
#include "pipeline_sequential.hpp"
#include "pipeline_solver.hpp"
#include "text.hpp"
#include "trip.hpp"
#include "sched/block.hpp"
#include "sched/bounds.hpp"
#include "sched/loop_report.hpp"

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
#include <functional>
#include <iterator>
#include <cctype>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <tuple>

namespace nesshi::sched {

using namespace pipe;

namespace {

assembler::AsmOptions asm_options(const PipelineOptions& opts = {}) {
    assembler::AsmOptions a;
    a.read_file = opts.read_file;
    return a;
}

// Integer registers that hold a known constant when bundle `at` starts, from the straight-line
// code before it back to the last label (a jump target: another way in): `li`, and `addi` of a
// known register; any other write forgets its register, a jump or call forgets them all.
// Conditional branches fall through to `at`.
std::map<int, std::int64_t> constants_at(const isa::ObjectFile& obj, const std::vector<std::vector<isa::Instr>>& bundles,
                                         std::uint32_t at) {
    std::uint32_t from = 0;
    for (const isa::Symbol& s : obj.symbols)
        if (s.kind == isa::SymbolKind::Code && s.value < at) from = std::max(from, s.value);
    std::map<int, std::int64_t> known;
    for (std::uint32_t b = from; b < at && b < bundles.size(); ++b) {
        std::map<int, std::int64_t> next = known; // a bundle reads its sources at issue
        for (const isa::Instr& in : bundles[b]) {
            const isa::OpInfo& info = in.info();
            if (info.kind == isa::Kind::Jump || info.kind == isa::Kind::JumpLink || info.kind == isa::Kind::JumpReg)
                next.clear(); // a call may change any register; after a jump only a label leads on
            for (const isa::RegOperand& o : isa::register_operands(in))
                if (o.write && o.file == isa::RegFile::Int) next.erase(o.reg);
            const std::int64_t imm = static_cast<std::int32_t>(in.imm);
            if (info.mnemonic == "li") next[in.rd] = static_cast<std::uint32_t>(imm);
            else if (info.mnemonic == "addi")
                if (const auto s = known.find(in.rs1); s != known.end())
                    next[in.rd] = static_cast<std::uint32_t>(s->second + imm);
        }
        known = std::move(next);
    }
    return known;
}

isa::ObjectFile assemble_or_fail(const std::string& text, std::string_view file, const isa::Machine& m,
                                 const std::string& what, const PipelineOptions& opts = {}) {
    const assembler::AsmResult res = assembler::assemble_string(text, file, m, asm_options(opts));
    if (!res.ok || res.warnings > 0)
        throw base::Error(base::SourceLoc(file), fmt::format("the {} does not assemble cleanly:\n{}", what, res.diagnostics));
    return res.object;
}

// The labels of the region with this ordinal in its file: __sa_... for the first (as with one).
std::string region_uid(int ordinal) { return ordinal == 0 ? "__sa" : fmt::format("__sa{}", ordinal); }

// Which region of a file pipeline_impl schedules, and what it may take. The file's other regions
// are written as their sequential meanings (the code around this one); `reusable` are registers
// the file names that the tool may take anyway (the scratch registers of regions already
// pipelined, live only inside them).
struct Target {
    std::size_t index = 0; // among the file's regions, in order
    int ordinal = 0;       // for its labels (region_uid)
    std::set<std::pair<int, int>> reusable;
};

struct Impl {
    PipelineResult res;
    std::string emitted; // the region's code alone
    Span span;           // its lines in the file (after `#if machine` sections are resolved)
};

// How far pipeline_impl goes: the sequential meaning between the region markers (every region
// between its own pair), the sequential meaning as a file, or the pipelined code.
enum class Upto { Markers, Linear, Pipelined };

Impl pipeline_impl(std::string_view text, std::string_view filename, const isa::Machine& m, const PipelineOptions& opts,
                   Upto upto, const Target& target = {}) {
    const bool linear_only = upto == Upto::Markers;
    const std::vector<std::string> lines = split_lines(machine_sections(text, filename, m));
    const std::vector<Span> spans = region_spans(lines, filename);
    if (target.index >= spans.size())
        fail(filename, 0, fmt::format("no region {}: the file has {} .pipeline region{}", target.index + 1, spans.size(),
                                      spans.size() == 1 ? "" : "s"));
    const Region r = parse_region(lines, filename, spans[target.index]);
    check_named_in_range(lines, filename, m);
    std::set<std::pair<int, int>> named = named_registers(lines);
    for (const auto& reg : target.reusable) named.erase(reg);

    const std::string uid = region_uid(target.ordinal);
    const Sequential q = sequential_meaning(r, named, m, filename, uid);
    // The lines [from, to) with every other region as its sequential meaning.
    auto around = [&](std::size_t from, std::size_t to) {
        std::string o;
        for (std::size_t i = from; i < to; ++i) {
            const auto other = std::find_if(spans.begin(), spans.end(), [&](const Span& sp) { return sp.first == i; });
            if (other == spans.end()) {
                o += lines[i] + "\n";
                continue;
            }
            const Region ro = parse_region(lines, filename, *other);
            const int k = static_cast<int>(other - spans.begin()) - static_cast<int>(target.index) + target.ordinal;
            const std::string seq = sequential_meaning(ro, named, m, filename, region_uid(k)).loop;
            o += linear_only ? std::string(kRegionBegin) + "\n" + seq + kRegionEnd + "\n" : seq;
            i = other->second;
        }
        return o;
    };
    const std::string before = around(0, r.begin), after = around(r.end + 1, lines.size());
    Impl impl;
    impl.span = spans[target.index];
    PipelineResult& res = impl.res;
    res.is_while = r.is_while;
    res.iteration_register = q.iteration_register;
    const std::string& loop = q.loop;
    if (linear_only) {
        res.linear = before + kRegionBegin + "\n" + loop + kRegionEnd + "\n" + after;
        return impl;
    }
    // Both files say first which machine they are for (a `# machine:` line of the source's is replaced).
    const std::string header = fmt::format("# machine: {}\n", m.reference());
    const std::string code_before = assembler::header_machine(before).empty() ? before : before.substr(before.find('\n') + 1);
    res.linear = header + code_before + loop + after;
    res.linear_region_at = header.size() + code_before.size();
    if (upto == Upto::Linear) return impl;
    const isa::ObjectFile lin = assemble_or_fail(res.linear, filename, m, "sequential meaning of the region", opts);
    const std::vector<std::vector<isa::Instr>> bundles = isa::decode_bundles(lin);
    std::uint32_t b0 = 0;
    for (const isa::Symbol& s : lin.symbols)
        if (s.name == uid + "_lin" && s.kind == isa::SymbolKind::Code) b0 = s.value;
    const std::uint32_t region_start = b0;
    std::vector<isa::Instr> instrs;
    for (const SrcOp& op : r.ops) {
        instrs.push_back(bundles[b0][0]);
        b0 += std::max<std::uint32_t>(1, m.latency_of(isa::kOps[op.opcode]));
    }
    const Graph g = build_graph(r, instrs, m, q.op_virtuals, constants_at(lin, bundles, region_start));
    // The trip count register is the loop's: the pipelined loop counts its passes in a register of
    // its own, so a value read or written there inside the region would differ from the
    // sequential meaning's, silently.
    if (!r.is_while)
        for (std::size_t k = 0; k < r.ops.size(); ++k)
            for (const isa::RegOperand& o : isa::register_operands(instrs[k]))
                if (o.file == isa::RegFile::Int && o.reg == r.trip_reg) {
                    const std::string& line = lines[static_cast<std::size_t>(r.ops[k].line - 1)];
                    std::size_t at = line.find(r.trip, line.find(r.ops[k].mnemonic) + r.ops[k].mnemonic.size());
                    while (at != std::string::npos && at + r.trip.size() < line.size() &&
                           std::isdigit(static_cast<unsigned char>(line[at + r.trip.size()])))
                        at = line.find(r.trip, at + 1); // r9, not r90
                    const std::size_t col = at == std::string::npos ? line.find_first_not_of(" \t") : at;
                    throw base::Error(base::SourceLoc(filename, r.ops[k].line, static_cast<int>(col + 1)),
                                      fmt::format("'{}' {} the trip count register {} inside the region: the pipelined "
                                                  "loop keeps its own count, so its value there is not defined (copy it "
                                                  "into another register before `.pipeline`, and step that copy)\n{}\n{}^",
                                                  r.ops[k].mnemonic, o.write ? "writes" : "reads", r.trip, line,
                                                  std::string(col, ' ')));
                }
    // Loop control in the kernel: `addi counter, counter, -1` and `bnez counter, kernel`.
    isa::Instr branch, counter;
    branch.opcode = isa::opcode("bnez");
    counter.opcode = isa::opcode("addi");
    counter.rd = counter.rs1 = 0; // register numbers do not matter for the resource checks
    res.rec_mii = g.ddg.rec_mii();
    // The loop control takes slots too; a while loop's exit test is its loop control.
    const ResBound res_bound = r.is_while ? res_mii(m, instrs) : res_mii(m, instrs, kLoopControl);
    res.res_mii = res_bound.ii();
    res.mii = std::max(res.rec_mii, res.res_mii);
    const int lo = opts.ii > 0 ? opts.ii : res.mii;
    const int hi = opts.ii > 0 ? opts.ii : res.mii + opts.max_ii_search;
    // The first II whose schedule also assembles: the kernel's taken-branch bubble (a machine's
    // branch_penalty) shifts the next pass, which the assembler's checks see and the MRT does not.
    std::optional<Schedule> sched;
    std::optional<Allocation> alloc_found;
    std::string emitted, why_not;
    int stages = 1;
    // One II: schedules in different op orders (until `deadline` when given), the first that
    // also assembles is kept.
    using Clock = std::chrono::steady_clock;
    // A schedule's code (registers allocated, text emitted), before it is assembled.
    struct Built {
        Schedule s;
        Allocation alloc;
        std::string code;
        int stages = 1;
        CountedShape shape; // a counted loop's
    };
    const TripDirective& trip = r.trip_count;
    // `first_least`: at least this many kernel copies (more amortise a taken-branch bubble);
    // `groups`: a counted loop's kernel repeats (Allocation::groups); 0: without .trip, those of
    // bubble_repeats (the while loop's rule) within most_repeats. They never lengthen a run of two
    // kernel iterations or more, and cost one bubble on a run of one.
    const bool by_trip = trip.min > 0 && !r.is_while;
    auto build = [&](const Schedule& s, int first_least = 1, int groups = 0) -> std::optional<Built> {
        std::optional<Allocation> fitted;
        try {
            // More kernel copies where the taken-branch bubble makes writes meet on a port.
            for (int least = first_least; least <= kMaxPortUnroll; least *= 2) {
                fitted = allocate(r, g, s, named, m, filename, least);
                const int pass = s.ii * fitted->unroll;
                fitted->groups = groups > 0                  ? groups
                                 : !r.is_while && !by_trip ? bubble_repeats(static_cast<int>(m.branch_penalty), pass, most_repeats(pass))
                                                            : 1;
                if (kernel_landings_ok(g, s, fitted->unroll, fitted->groups, m, false)) break;
                if (kernel_landings_ok(g, s, fitted->unroll, fitted->groups, m, true)) {
                    fitted->entry_nops = static_cast<int>(m.branch_penalty);
                    break;
                }
                if (fitted->unroll >= kMaxPortUnroll) {
                    why_not = fmt::format("II {}: writes meet on a register file's ports across the kernel's back edge "
                                          "(its {}-cycle branch bubble) with up to {} kernel copies", s.ii,
                                          m.branch_penalty, fitted->unroll);
                    return std::nullopt;
                }
                least = fitted->unroll;
            }
        } catch (const RegisterPressure& e) {
            const std::string what = e.what();
            why_not = fmt::format("II {}: {}", s.ii, what.substr(std::min(what.size(), what.find("error: ") + 7)));
            return std::nullopt;
        }
        Built b{s, std::move(*fitted), "", 1, {}};
        Emitted e = emit_region(r, g, s, b.alloc, m, uid, trip.min, &b.shape);
        b.code = std::move(e.code);
        b.stages = e.stages;
        return b;
    };
    // Whether the code assembles, in the file (a while loop's entry, or a counted loop's without
    // its zero-trip test, may get nops first).
    auto assembles = [&](Built& b) {
        std::string& code = b.code;
        assembler::AsmResult check = assembler::assemble_string(before + code + after, filename, m, asm_options(opts));
        // A while loop starts with its first pass (the counted loop with its trip test, unless
        // .trip drops it): results of the code before it may still be in flight. As many nops as
        // the assembler's check asks.
        std::uint32_t longest = 1;
        for (std::uint32_t l : m.latency) longest = std::max(longest, l);
        auto clean = [](const assembler::AsmResult& a) { return a.ok && a.warnings == 0; };
        if ((r.is_while || !b.shape.guard) && !clean(check) && longest > 1) {
            // The most nops first: when even they do not help, the fault is not at the entry
            // (one assembly, not one per count); else the fewest that do.
            std::string nops;
            for (std::uint32_t k = 1; k < longest; ++k) nops += "        nop\n";
            assembler::AsmResult most = assembler::assemble_string(before + nops + code + after, filename, m, asm_options(opts));
            if (!clean(most)) check = std::move(most);
            for (std::uint32_t lead = 1; clean(most) && !clean(check) && lead < longest; ++lead) {
                code = "        nop\n" + code;
                ++b.shape.lead;
                check = lead + 1 == longest ? std::move(most)
                                            : assembler::assemble_string(before + code + after, filename, m, asm_options(opts));
            }
        }
        if (!check.ok || check.warnings > 0) {
            why_not = fmt::format("II {}: {}", b.s.ii, check.diagnostics.substr(0, check.diagnostics.find('\n')));
            return false;
        }
        return true;
    };
    CountedShape shape_found;
    auto keep = [&](Built&& b) {
        shape_found = b.shape;
        sched = std::move(b.s);
        emitted = std::move(b.code);
        stages = b.stages;
        alloc_found = std::move(b.alloc);
    };
    // A schedule is kept when its code also assembles (with at least `copies` kernel copies).
    auto accept = [&](const Schedule& s, int copies = 1) {
        std::optional<Built> b = build(s, copies);
        if (!b || !assembles(*b)) return false;
        keep(std::move(*b));
        return true;
    };
    // Each schedule found is first tried with its ops moved by whole stages to fewer stages and
    // shorter lifetimes (same reservation table), then as found if that one fails to assemble.
    const std::vector<Dep>& edges = g.ddg.edges;
    const std::vector<StageValue> values = stage_values(g);
    const IterationBounds bounds = iteration_bounds(g, m);
    int scheduled_count = 0; // modulo schedules found, whether or not their code assembled
    auto shifted = [&](const Schedule& s) {
        ++scheduled_count;
        std::vector<Schedule> out;
        Schedule c = s;
        c.time = shift_stages(edges, values, s.time, s.ii);
        c.normalise();
        if (c.time != s.time) out.push_back(std::move(c));
        out.push_back(s);
        return out;
    };
    // The schedule at s's II whose iteration ends soonest, by the solver (pipeline_solver.hpp),
    // as `shifted` gives it; none when the solver finds nothing shorter, or when s has the fewest
    // stages any schedule could have or is within half an II of the longest path (a run would
    // gain a few cycles at most, and the search costs up to its budget). Once per region, at
    // the first schedule worth it: at a larger II the stages fall anyway, and a region whose IIs
    // fail to assemble would pay the search at each.
    // Whether runs are short enough for it (PipelineOptions::shorten): the trips `.trip` expects,
    // else those the trip register holds on entry when known; "" when worth it, else why not.
    const std::int64_t runs_of = trip.min > 0 ? trip.expected : g.trip.value_or(0);
    auto why_not_shorten = [&](const Schedule& s) -> std::string {
        switch (opts.shorten) {
        case PipelineOptions::Shorten::Always: return "";
        case PipelineOptions::Shorten::Never: return "not asked for";
        case PipelineOptions::Shorten::Auto: break;
        }
        if (r.is_while) return "a while loop's runs are taken to be long";
        if (trip.min <= 0 && !g.trip) return "runs of unknown length are taken to be long (.trip N says how long)";
        if (runs_of <= 0) return fmt::format("the trip register holds {} on entry: no run to shorten", runs_of);
        const std::int64_t length = iteration_length(g, s), gain = length - bounds.length;
        const std::int64_t run = (runs_of - 1) * s.ii + length;
        if (gain * 100 >= kShortenWorthPercent * run) return "";
        return fmt::format("at {} trips it would gain at most {} of {} cycles a run, under {}%", runs_of, gain, run,
                           kShortenWorthPercent);
    };
    // Whether the solver could shorten `s` enough to matter: its iteration half an II or more above
    // the longest path, and more stages than the fewest the II allows.
    auto could_shorten = [&](const Schedule& s) {
        return iteration_length(g, s) >= bounds.length + (s.ii + 1) / 2 && s.stages() > bounds.fewest_stages(s.ii);
    };
    bool solver_ran = false;
    auto shortest = [&](const Schedule& s) {
        if (solver_ran || !could_shorten(s) || !why_not_shorten(s).empty()) return std::vector<Schedule>{};
        solver_ran = true;
        const std::optional<Schedule> shorter = shortest_schedule(g, m, s, r.is_while ? r.exit_op : -1, kSolverBudget);
        return shorter ? shifted(*shorter) : std::vector<Schedule>{};
    };
    // The caller has checked that the dependences admit stage numbers at this II (Ddg::admits).
    auto try_ii = [&](int ii, std::optional<Clock::time_point> deadline) {
        if (r.is_while && !deadline) { // of every attempt's schedule, the fewest stages, then the smallest
            // unroll, is the cheapest to enter and to leave (a while loop does both often); the
            // earlier attempt on a tie. Ranked first, then assembled in that order until one does
            // (assembling the file is the expensive step).
            struct Ranked {
                int stages, unroll;
                Schedule s;
            };
            std::vector<Ranked> ranked;
            // Attempts at a stage limit (0: none); under a limit, until one keeps to it.
            auto attempts = [&](int limit) {
                bool within = false;
                for (int attempt = 0; attempt < 2 * kAttemptsPerII && !(within && limit > 0); ++attempt) {
                    std::optional<Schedule> found = modulo_schedule(g, m, ii, branch, counter, attempt, r.exit_op, limit);
                    if (!found) continue;
                    for (Schedule& s : shifted(*found)) {
                        const int st = s.stages();
                        try {
                            ranked.push_back({st, allocate(r, g, s, named, m, filename).unroll, std::move(s)});
                            within = within || limit == 0 || st <= limit;
                        } catch (const RegisterPressure& e) {
                            const std::string what = e.what();
                            why_not = fmt::format("II {}: {}", ii, what.substr(std::min(what.size(), what.find("error: ") + 7)));
                        }
                    }
                }
                std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
                    return std::tie(a.stages, a.unroll) < std::tie(b.stages, b.unroll);
                });
                return within;
            };
            attempts(0);
            // Then each stage fewer than the best so far, as long as some attempt keeps to it: a
            // run pays about (stages - 1) x II to fill and drain, and the loops of a kernel run often.
            int limit = ranked.empty() ? 0 : ranked.front().stages - 1;
            while (limit >= 1 && attempts(limit)) --limit;
            if (!ranked.empty()) { // the shortest iteration at this II, first on a tie
                std::vector<Ranked> solved;
                for (Schedule& s : shortest(ranked.front().s)) {
                    try {
                        solved.push_back({s.stages(), allocate(r, g, s, named, m, filename).unroll, std::move(s)});
                    } catch (const RegisterPressure&) {
                    }
                }
                ranked.insert(ranked.begin(), std::make_move_iterator(solved.begin()), std::make_move_iterator(solved.end()));
                std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
                    return std::tie(a.stages, a.unroll) < std::tie(b.stages, b.unroll);
                });
            }
            for (const Ranked& k : ranked)
                if (accept(k.s)) return true;
            return false;
        }
        for (int attempt = 0; deadline ? Clock::now() < *deadline : attempt < kAttemptsPerII; ++attempt) {
            std::optional<Schedule> s = modulo_schedule(g, m, ii, branch, counter, attempt, r.is_while ? r.exit_op : -1);
            if (!s) continue;
            std::vector<Schedule> tries = shifted(*s);
            if (!deadline) { // the solver's schedule first (once per region)
                const std::vector<Schedule> better = shortest(tries.front());
                // With a taken-branch bubble it keeps the kernel copies of the schedule it
                // shortens: its shorter lifetimes would need fewer, and a kernel of fewer copies
                // pays the bubble more often per iteration (livermore1 on os-real: one copy at
                // 5 cycles per iteration against two at 4.5).
                int copies = 1;
                if (!better.empty() && m.branch_penalty > 0)
                    if (const std::optional<Built> b = build(tries.front())) copies = b->alloc.unroll;
                for (const Schedule& k : better)
                    if (accept(k, copies)) return true;
            }
            for (const Schedule& k : tries)
                if (accept(k)) return true;
        }
        return false;
    };
    // `.trip`: every schedule found at an II is costed by its whole run at the expected trip
    // count (whole_run_cycles, from the code's shape); they are assembled cheapest first, and the
    // first that assembles is kept when it beats the best so far. At the first II that works, the
    // schedule the rule without .trip takes (the first found that assembles) is assembled first:
    // the report compares with it.
    std::optional<TripChoice> choice;
    auto option = [&](const Built& b) {
        TripChoice::Option o;
        static_cast<RunParts&>(o) = whole_run_parts(b.shape, trip.expected);
        o.ii = b.s.ii, o.stages = b.stages, o.unroll = b.alloc.unroll, o.groups = b.alloc.groups, o.cycles = o.total();
        return o;
    };
    auto try_ii_trip = [&](int ii) {
        std::vector<Built> found;
        std::set<std::vector<int>> seen;
        for (int attempt = 0; attempt < kAttemptsPerII; ++attempt) {
            std::optional<Schedule> s = modulo_schedule(g, m, ii, branch, counter, attempt, -1);
            if (!s) continue;
            std::vector<Schedule> tries = shifted(*s);
            { // the solver's schedule too (once per region)
                std::vector<Schedule> better = shortest(tries.front());
                tries.insert(tries.end(), better.begin(), better.end());
            }
            for (const Schedule& k : tries) {
                if (!seen.insert(k.time).second) continue;
                std::optional<Built> b = build(k, 1, 1);
                if (!b) continue;
                const int copies = b->alloc.unroll;
                found.push_back(std::move(*b));
                // With a taken-branch bubble, the kernel repeated 2, 4, 8 times (each copy tests for
                // the last iteration, so no remainder and no register more, only code) as far as
                // most_repeats allows: one bubble per pass of the longer kernel. The whole-run cost
                // decides.
                if (m.branch_penalty > 0)
                    for (int groups = 2; groups <= most_repeats(copies * ii); groups *= 2)
                        if (std::optional<Built> c = build(k, copies, groups); c && c->alloc.unroll == copies)
                            found.push_back(std::move(*c));
            }
        }
        std::vector<TripChoice::Option> cost;
        for (const Built& b : found) cost.push_back(option(b));
        std::optional<std::size_t> first_ok;
        if (!choice) {
            for (std::size_t k = 0; k < found.size() && !first_ok; ++k)
                if (assembles(found[k])) first_ok = k;
            if (!first_ok) return false;
            cost[*first_ok] = option(found[*first_ok]); // with the nops its entry may have got
            choice = TripChoice{trip.min, trip.expected, trip.line, cost[*first_ok], cost[*first_ok], 0, ii, ii};
        }
        choice->candidates += static_cast<int>(found.size());
        choice->ii_last = ii;
        std::vector<std::size_t> order(found.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { // the smaller code on a tie
            const int ka = cost[a].unroll * cost[a].groups, kb = cost[b].unroll * cost[b].groups;
            return std::tie(cost[a].cycles, cost[a].stages, ka, cost[a].unroll) < std::tie(cost[b].cycles, cost[b].stages, kb, cost[b].unroll);
        });
        for (std::size_t k : order) {
            if (!first_ok && cost[k].cycles >= choice->chosen.cycles) break;
            // Entry nops (assembles) are known only once assembled: the order is by the cost
            // without them (they are rare: code just before the region feeding it), and one that
            // they make no cheaper than the one to beat is passed over.
            if (k != first_ok) {
                if ((first_ok && k < *first_ok) || !assembles(found[k])) continue; // those before it failed
                const std::int64_t with_nops = option(found[k]).cycles;
                if (first_ok ? with_nops > cost[*first_ok].cycles : with_nops >= choice->chosen.cycles) continue;
            }
            choice->chosen = option(found[k]);
            choice->short_path = found[k].shape.short_path;
            keep(std::move(found[k]));
            return true;
        }
        return false;
    };
    int last_tried = hi;
    // Why each II below the one taken failed, for the report: runs of IIs that failed alike.
    struct Tried {
        int first, last;
        // 0: no stage numbers satisfy the recurrences, 1: no modulo schedule found, 2: none
        // assembled, 3: none exists (the constraint model), 4: one exists that the search missed
        int kind;
        std::string detail;
    };
    std::vector<Tried> tried;
    // An II the search found nothing at: the constraint model (pipeline_exact.hpp), within a node
    // budget, tells whether a table exists (counted loops; the model does not search while loops).
    auto decide = [&](int ii) {
        if (r.is_while) return 1;
        const ExactRun ex = exact_schedule(g, m, ii, branch, counter, Clock::time_point::max(), [](const Schedule&) { return true; },
                                           kProofNodes);
        return ex.outcome == ExactOutcome::Exhausted ? 3 : ex.outcome == ExactOutcome::Accepted ? 4 : 1;
    };
    for (int ii = lo, unscheduled = 0; ii <= hi; ++ii) {
        const int before_ii = scheduled_count;
        const bool feasible = g.ddg.admits(ii);
        if (feasible && (by_trip ? try_ii_trip(ii) : try_ii(ii, std::nullopt))) break;
        int kind = !feasible ? 0 : scheduled_count == before_ii ? 1 : 2;
        if (kind == 1) kind = decide(ii);
        const std::string detail = kind == 2 ? why_not.substr(std::min(why_not.size(), why_not.find(": ") + 2)) : "";
        if (!tried.empty() && tried.back().kind == kind && tried.back().last + 1 == ii)
            tried.back().last = ii, tried.back().detail = detail;
        else
            tried.push_back({ii, ii, kind, detail});
        unscheduled = scheduled_count == before_ii ? unscheduled + 1 : 0;
        if (opts.max_unscheduled_iis > 0 && unscheduled >= opts.max_unscheduled_iis) {
            last_tried = ii;
            break;
        }
    }
    if (choice) {
        // Larger IIs while one could still be cheaper: the prologue and the kernel passes alone
        // take EXPECTED x II cycles.
        // No further than that length: a kernel pass as long gains nothing on the sequential loop.
        int sequential = 1 + std::max(1, static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]));
        for (const Node& nd : g.nodes) sequential += std::max(1, nd.latency);
        for (int ii = sched->ii + 1; ii <= std::min(hi, sequential); ++ii) {
            if (static_cast<std::int64_t>(trip.expected) * std::min(ii, sequential) >= choice->chosen.cycles) break;
            choice->ii_last = ii;
            if (g.ddg.admits(ii)) try_ii_trip(ii);
        }
    }
    // --exact: every modulo table at each II from the bound up to the one found (a constraint
    // model, pipeline_exact.hpp); the first II with a schedule that assembles is the answer, and
    // it is proven optimal when every II below it was exhausted with no table the build accepts.
    std::string exact_note;
    if (sched && opts.exact_seconds > 0) {
        if (choice) {
            exact_note = "--exact is not combined with .trip yet (the schedule is chosen by whole-run cycles)";
        } else if (r.is_while && sched->ii > res.mii) {
            exact_note = "--exact is not implemented for .pipeline while loops yet (heuristic schedule only)";
        } else if (sched->ii == res.mii) {
            exact_note = "II proven optimal: it equals the lower bound max(ResMII, RecMII)";
        } else {
            const auto start = Clock::now();
            const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opts.exact_seconds));
            const int found = sched->ii;
            std::uint64_t nodes = 0;
            int proven_below = res.mii; // every II in [res.mii, proven_below) has no modulo schedule
            std::string open;           // why the bound is not proven
            for (int ii = res.mii; ii < found; ++ii) {
                if (!g.ddg.admits(ii)) {
                    if (open.empty()) proven_below = ii + 1;
                    continue;
                }
                const ExactRun ex = exact_schedule(g, m, ii, branch, counter, deadline, accept);
                const ExactOutcome o = ex.outcome;
                const std::uint64_t tables = ex.tables;
                nodes += ex.nodes;
                if (o == ExactOutcome::Accepted) break;
                if (o == ExactOutcome::Timeout) {
                    open = fmt::format("II {} undecided after {} s{}", ii, opts.exact_seconds,
                                       tables ? fmt::format(" ({} modulo schedule{} found did not assemble; the last: {})",
                                                            tables, tables == 1 ? "" : "s",
                                                            why_not.substr(std::min(why_not.size(), why_not.find("error: ") + 7)))
                                              : "");
                    break;
                }
                if (tables > 0 && open.empty())
                    open = fmt::format("II {} has {} modulo schedule{} but none assembles", ii, tables, tables == 1 ? "" : "s");
                if (open.empty()) proven_below = ii + 1;
            }
            const double secs = std::chrono::duration<double>(Clock::now() - start).count();
            const std::string searched = fmt::format("Gecode, {} nodes in {:.2f} s", nodes, secs);
            // With a taken-branch bubble the search covers only tables the build's port check
            // across the kernel's back edge passes (pipeline_exact.cpp).
            const std::string back_edge = m.branch_penalty > 0 ? " keeps the write ports across the kernel's back edge" : "";
            const std::string improved = sched->ii < found ? fmt::format(" (the heuristic found II {})", found) : "";
            if (open.empty() && proven_below >= sched->ii)
                exact_note = sched->ii > res.mii
                                 ? fmt::format("II proven optimal{}: no modulo schedule at II {}..{}{} ({})", improved, res.mii,
                                               sched->ii - 1, back_edge, searched)
                                 : fmt::format("II proven optimal{}: it equals the lower bound ({})", improved, searched);
            else
                exact_note = fmt::format("best found{}, bound not proven: {}{} ({})", improved, open,
                                         proven_below > res.mii ? fmt::format("; none at II {}..{}", res.mii, proven_below - 1) : "",
                                         searched);
        }
    }
    if (!sched)
        fail(filename, static_cast<int>(r.begin + 1),
             fmt::format("no modulo schedule found for II {}..{} (MII {}){}", lo, last_tried, res.mii,
                         why_not.empty() ? "" : "; the last that scheduled did not assemble: " + why_not));
    const Allocation& alloc = *alloc_found;
    res.ii = sched->ii;
    res.stages = stages;
    res.iteration_cycles = iteration_length(g, *sched);
    res.iteration_lower = bounds.length;
    res.unroll = alloc.unroll;
    res.groups = alloc.groups;
    res.min_pipelined_trip = r.is_while ? 0 : shape_found.min_pipelined;
    res.trip_register = r.trip;
    if (r.is_while) res.exit_stage = sched->time[static_cast<std::size_t>(r.exit_op)] / sched->ii;
    res.scratch = alloc.scratch;
    res.min_trip = by_trip ? trip.min : 0;
    int proven_mii = res.mii;
    for (const Tried& t : tried)
        if (t.first <= proven_mii && proven_mii <= t.last && (t.kind == 0 || t.kind == 3)) proven_mii = t.last + 1;
    res.loops = {{static_cast<int>(r.begin + 1), r.is_while, res.ii, res.mii, res.res_mii, res.rec_mii, res.stages, res.unroll,
                  std::min(proven_mii, res.ii), res.groups, choice, res.iteration_cycles, res.iteration_lower, {}}};
    for (const auto& [f, reg] : named) res.source_registers.push_back(reg_name(static_cast<isa::RegFile>(f), reg));

    std::string rep;
    rep += fmt::format("# SOFTWARE PIPELINE INFORMATION ({} on {}, lines {}-{})\n", filename, m.name, r.begin + 1, r.end + 1);
    if (r.is_while)
        rep += fmt::format("#   operations per iteration   {} (a while loop: its exit test is the kernel's branch)\n", r.ops.size());
    else
        rep += fmt::format("#   operations per iteration   {} (+ 2 for loop control in the kernel)\n", r.ops.size());
    rep += fmt::format("#   resource bound (ResMII)    {}  ({}, loop control included)\n", res.res_mii, res_bound.binds);
    const std::vector<int> critical = res.rec_mii <= 1 ? std::vector<int>{} : g.ddg.circuit_above(res.rec_mii - 1);
    const std::string circuit = critical_circuit(g, r, critical);
    rep += fmt::format("#   recurrence bound (RecMII)  {}{}\n", res.rec_mii, circuit.empty() ? "" : "  (" + circuit + ")");
    if (const std::string hint = alias_hint(g, critical); !hint.empty()) rep += "#     " + hint + "\n";
    rep += fmt::format("#   ii = {}  schedule found with {} iteration{} in parallel{}\n", res.ii, res.stages,
                       res.stages == 1 ? "" : "s",
                       res.ii == res.mii         ? " (at the bound)"
                       : res.loops[0].proven_mii == res.ii ? fmt::format(" ({} above the MII; no modulo schedule exists below it)", res.ii - res.mii)
                                                 : fmt::format(" ({} above the MII)", res.ii - res.mii));
    rep += fmt::format("#   one iteration {} cycles from its first issue to its last landing (its longest path: {})\n",
                       res.iteration_cycles, res.iteration_lower);
    if (!solver_ran && could_shorten(*sched))
        if (const std::string why = why_not_shorten(*sched); !why.empty())
            rep += fmt::format("#   not shortened by the solver: {} (--shorten searches anyway)\n", why);
    if (!tried.empty()) {
        std::string why;
        for (const Tried& t : tried) {
            const std::string iis = t.first == t.last ? fmt::format("II {}", t.first) : fmt::format("IIs {}..{}", t.first, t.last);
            why += fmt::format("{}{}: {}", why.empty() ? "" : "; ", iis,
                               t.kind == 0   ? "no stage numbers satisfy the recurrences"
                               : t.kind == 1 ? "no modulo schedule found"
                               : t.kind == 3 ? fmt::format("no modulo schedule exists{} (proven by the constraint model)",
                                                           m.branch_penalty > 0 ? " that keeps the write ports across the kernel's back edge" : "")
                               : t.kind == 4 ? "a modulo schedule exists that the search missed (the constraint model found one; try --exact)"
                                             : "schedules found, none assembled (the last: " + t.detail + ")");
        }
        rep += fmt::format("#   below it: {}\n", why);
    }
    if (!exact_note.empty()) rep += "#   " + exact_note + "\n";
    rep += fmt::format("#   kernel unrolled {}x (modulo variable expansion)\n", res.unroll);
    const int kernel_copies = res.unroll * alloc.groups;
    if (alloc.groups > 1)
        rep += fmt::format("#   kernel repeated {}x ({} copies, one back branch)\n", alloc.groups, kernel_copies);
    if (m.branch_penalty > 0)
        rep += fmt::format("#   taken-branch bubble {} cycle{} per kernel pass: {:.2f} cycles per iteration in the kernel\n",
                           m.branch_penalty, m.branch_penalty == 1 ? "" : "s",
                           static_cast<double>(kernel_copies * res.ii + static_cast<int>(m.branch_penalty)) / kernel_copies);
    if (alloc.entry_nops > 0)
        rep += fmt::format("#   kernel entered after {} nop{} (as long as the bubble, so writes from the prologue and from the "
                           "back edge meet no others on a port)\n", alloc.entry_nops, alloc.entry_nops == 1 ? "" : "s");
    if (r.is_while)
        rep += while_report(g, r, *sched, res);
    else if (!shape_found.short_path)
        rep += fmt::format("#   minimum pipelined trip count {} (.trip's minimum is at least that: no sequential copy)\n",
                           res.min_pipelined_trip);
    else
        rep += fmt::format("#   minimum pipelined trip count {} (fewer run the sequential copy)\n", res.min_pipelined_trip);
    if (choice) rep += choice->text();
    std::array<std::set<std::string>, 2> given; // the registers the kernel's copies take, per file
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        std::string regs;
        for (const std::string& s : alloc.regs[v]) {
            regs += (regs.empty() ? "" : " ") + s;
            given[r.virtuals[v].file == isa::RegFile::Int ? 0 : 1].insert(s);
        }
        rep += fmt::format("#   {:<10} lifetime {:>3} cycles -> {}\n", r.virtuals[v].name, alloc.lifetime[v], regs);
    }
    const std::vector<TableRow> rows = schedule_rows(g, r, *sched, m);
    LoopReport picture = schedule_picture(g, r, *sched, rows, alloc.lifetime, m, filename,
                                          res.ii == res.mii ? "at the bound" : fmt::format("{} above the MII", res.ii - res.mii));
    picture.res_mii = res.res_mii;
    picture.rec_mii = res.rec_mii;
    res.loops[0].svg = picture.svg();
    // MaxLive: the most values alive in one cycle of the kernel, per file (a lower bound on the
    // registers any allocation needs); beside it, the registers the kernel's copies were given.
    if (!r.virtuals.empty())
        rep += fmt::format("#   MaxLive: IRF {}, FPRF {}; registers allocated: IRF {} of {}, FPRF {} of {}\n", picture.max_live[0],
                           picture.max_live[1], given[0].size(), m.regs[0].count, given[1].size(), m.regs[1].count);
    rep += mrt_text(rows);
    res.report = rep;

    res.code = code_before + emitted + after;
    res.pipelined = header + rep + res.code;
    res.pipelined_region_at = header.size() + rep.size() + code_before.size();
    impl.emitted = emitted;
    return impl;
}

} // namespace

PipelineResult pipeline_source(std::string_view text, std::string_view filename, const isa::Machine& m,
                               const PipelineOptions& opts) {
    std::vector<std::string> lines = split_lines(machine_sections(text, filename, m));
    const std::size_t n = region_spans(lines, filename).size();
    if (opts.region || n == 1) {
        Target t;
        t.index = opts.region.value_or(0);
        t.ordinal = static_cast<int>(t.index);
        PipelineResult r = pipeline_impl(text, filename, m, opts, Upto::Pipelined, t).res;
        r.regions = static_cast<int>(n);
        return r;
    }
    // Several regions: one after another, the last first (so each one's lines, and those before
    // it, keep their numbers in reports and errors), each scheduled with the later ones as their
    // pipelined code and the earlier ones as their sequential meanings; a region's scratch
    // registers are free again for the next (they are live only inside it).
    const std::string linear = pipeline_impl(text, filename, m, opts, Upto::Linear).res.linear; // every region sequential
    PipelineResult all;
    std::string reports;
    std::vector<LoopSummary> loops;
    Target t;
    for (std::size_t k = n; k-- > 0;) {
        t.index = k;
        t.ordinal = static_cast<int>(k);
        std::string current;
        for (const std::string& l : lines) current += l + "\n";
        Impl step = pipeline_impl(current, filename, m, opts, Upto::Pipelined, t);
        all = step.res;
        reports = step.res.report + reports;
        loops.insert(loops.begin(), step.res.loops.begin(), step.res.loops.end());
        for (const std::string& reg : step.res.scratch) {
            if (const auto named = assembler::register_named(reg)) t.reusable.insert({static_cast<int>(named->first), named->second});
        }
        std::vector<std::string> spliced(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(step.span.first));
        for (const std::string& l : split_lines(step.emitted)) spliced.push_back(l);
        spliced.insert(spliced.end(), lines.begin() + static_cast<std::ptrdiff_t>(step.span.second + 1), lines.end());
        lines = std::move(spliced);
    }
    std::string code;
    for (const std::string& l : lines) code += l + "\n";
    if (!assembler::header_machine(code).empty()) code = code.substr(code.find('\n') + 1);
    all.regions = static_cast<int>(n);
    all.linear_region_at.reset(); // the offsets of one region's files, not of these
    all.pipelined_region_at.reset();
    all.linear = linear;
    all.loops = loops;
    all.report = reports;
    all.code = code;
    all.pipelined = fmt::format("# machine: {}\n", m.reference()) + reports + code;
    return all;
}

std::string sequential_region(std::string_view text, std::string_view filename, const isa::Machine& m) {
    return pipeline_impl(text, filename, m, {}, Upto::Markers).res.linear;
}

std::vector<int> region_lines(std::string_view text, std::string_view filename, const isa::Machine& m) {
    std::vector<int> out;
    for (const Span& s : region_spans(split_lines(machine_sections(text, filename, m)), filename)) out.push_back(static_cast<int>(s.first + 1));
    return out;
}

std::string restore_region(std::string_view legalized, std::string_view original) {
    // The original's regions, .pipeline to .endpipeline, in order: the k-th goes back between the
    // k-th pair of markers.
    std::vector<std::string> regions;
    bool in_region = false;
    for (const std::string& o : split_lines(original)) {
        const std::string code = strip_comment(o);
        if (opens_region(code)) {
            in_region = true;
            regions.emplace_back();
        }
        if (in_region) regions.back() += o + "\n";
        if (code == ".endpipeline") in_region = false;
    }
    std::string out;
    bool inside = false;
    std::size_t next = 0;
    for (const std::string& l : split_lines(legalized)) {
        if (l == kRegionBegin) {
            inside = true;
            if (next < regions.size()) out += regions[next++];
            continue;
        }
        if (l == kRegionEnd) {
            inside = false;
            continue;
        }
        if (!inside) out += l + "\n";
    }
    return out;
}

} // namespace nesshi::sched
