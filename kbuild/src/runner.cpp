#include "kbuild/runner.hpp"

#include "hybrid_kernel.hpp"

#include "kbuild/workloads.hpp"
#include "presets.hpp"
#include "schedule_cache.hpp"

#include "kbuild/scene_sample.hpp"

#include "assembler/assembler.hpp"
#include "sched/block.hpp"
#include "sched/legalize.hpp"
#include "sched/pipeline.hpp"

#include "base/error.hpp"
#include "base/hash.hpp"
#include "kernels/abi.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <future>
#include <map>
#include <mutex>
#include <bit>
#include <charconv>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace nesshi::kbuild {

namespace {

// Whether `m` is the machine the scheduled kernel `text` names on its first line (under any name).
bool scheduled_for(std::string_view text, const isa::Machine& m) {
    const isa::Machine* p = detail::preset(assembler::header_machine(text));
    return p && p->same_as(m);
}

// Scheduling a kernel for another machine costs about 0.1 s, and a sweep or the paper asks for the
// same one in every cell: the result is kept for the process, by a hash of every source file,
// the kernel's path and the machine's fingerprint.
struct Scheduled {
    std::string text;
    KernelBuild build;
    std::string name; // what it is assembled as: the .pk, or the committed .s when that was chosen
};

std::string schedule_key(const kernels::SourceSet& sources, const std::string& path, const isa::Machine& m) {
    base::Fnv1a h;
    for (const kernels::SourceFile& f : sources.files) h.add(f.path).add(std::string_view("\0", 1)).add(f.text);
    return base::hex64(h.value()) + "/" + path + "/" + base::hex64(m.fingerprint());
}

struct Candidates;
std::mutex schedule_mutex;
std::map<std::string, std::shared_ptr<const Candidates>>& schedule_cache() {
    static std::map<std::string, std::shared_ptr<const Candidates>> cache;
    return cache;
}

// The preset `m` is under another name (a file that only inherits it, a copy), else `m` itself: the
// preset's kernels, compiled runs and statistics, byte for byte.
const isa::Machine& canonical(const isa::Machine& m) {
    for (const isa::Machine& p : detail::presets())
        if (p.same_as(m)) return p;
    return m;
}

// Named "kernels/<path>" in diagnostics and line tables, so its "../abi.inc" is "kernels/abi.inc".
const std::string kPrefix = "kernels/";

// An alternative source's loops search this far above their MII (the main source's, the
// pipeliner's default): a machine where they do not schedule near their bound keeps the main
// source, and does not pay minutes to find out.
constexpr int kAlternativeIiSearch = 16;
constexpr int kAlternativeUnscheduled = 8; // IIs in a row with no modulo schedule at all: give up

// The pipeliner's reports of a .pk's regions, scheduled in a text whose lines before each region
// differ from the .pk's: each region's block (one per `.pipeline`, in order) with its line numbers
// moved to the .pk's, where its `.pipeline` is at `lines[k]` (a region's own text is the .pk's).
std::string with_source_lines(const std::string& report, const std::vector<int>& lines) {
    static const std::regex head(R"(lines (\d+)-\d+\))"), number(R"(\b(lines? )(\d+)(-(\d+))?)");
    const std::string marker = "# SOFTWARE PIPELINE INFORMATION";
    std::size_t at = report.find(marker);
    std::string out = report.substr(0, at);
    for (std::size_t k = 0; at != std::string::npos; ++k) {
        const std::size_t next = report.find(marker, at + marker.size());
        const std::string block = report.substr(at, next == std::string::npos ? std::string::npos : next - at);
        at = next;
        std::smatch m;
        if (k >= lines.size() || !std::regex_search(block, m, head)) {
            out += block;
            continue;
        }
        const int shift = lines[k] - std::stoi(m[1]);
        auto from = block.cbegin();
        for (std::sregex_iterator it(block.begin(), block.end(), number), end; it != end; ++it) {
            const std::smatch& x = *it;
            out.append(from, x[0].first);
            out += x[1].str() + std::to_string(std::stoi(x[2]) + shift);
            if (x[4].matched) out += "-" + std::to_string(std::stoi(x[4]) + shift);
            from = x[0].second;
        }
        out.append(from, block.cend());
    }
    return out;
}

// sched::legalize's check: the diagnostics of `text` assembled as `name` for m, none when it assembles.
std::function<std::optional<std::string>(const std::string&)> assembles_as(const std::string& name, const isa::Machine& m,
                                                                           const assembler::AsmOptions& opts) {
    return [&name, &m, &opts](const std::string& t) -> std::optional<std::string> {
        assembler::AsmResult a = assembler::assemble_string(t, name, m, opts);
        if (a.ok) return std::nullopt;
        return a.diagnostics;
    };
}

// The source `pk` ("ic/intersect.pk") scheduled for m: the hand-scheduled code between its
// blocks first gets the nops m's latencies need (with its blocks written sequentially), then the
// scheduled file once more (blocks may start earlier than written). Its `.pipeline` regions are
// modulo-scheduled for m: the code around them is legalized with the regions as their sequential
// meanings, then they go back in. `#if machine` sections are resolved for m first.
Scheduled schedule_source(const kernels::SourceSet& sources, const std::string& pk, const isa::Machine& m,
                          const assembler::AsmOptions& opts, bool alternative) {
    Scheduled out;
    out.name = kPrefix + pk;
    const std::string& name = out.name;
    KernelBuild& b = out.build;
    b.machine = m.name;
    const auto assembles = assembles_as(name, m, opts);
    const std::string src = sched::machine_sections(sources.text(pk), name, m);
    const bool region = src.find("\n        .pipeline") != std::string::npos;
    try {
        const sched::Legalized hand = sched::legalize(region ? sched::sequential_region(src, name, m) : src, name,
                                                      [&](const std::string& t) -> std::optional<std::string> {
            try {
                (void)sched::pack_source(t, name, m, opts);
                return std::nullopt;
            } catch (const base::Error& e) {
                return std::string(e.what());
            }
        });
        const sched::PackResult pr = sched::pack_source(hand.text, name, m, opts);
        std::string around = pr.text;
        int region_nops = 0;
        if (region) { // the blocks are bundled now: the file assembles around the regions
            // Bundled blocks end sooner than their sequential text did, so a value they leave in
            // flight can reach hand code that was legal before (around a back edge too): legalize
            // once more with the regions still sequential, so the pipeliner's own assembly of the
            // sequential meaning is legal.
            const sched::Legalized seq = sched::legalize(around, name, assembles);
            around = seq.text;
            region_nops = seq.nops;
            sched::PipelineOptions po;
            po.read_file = opts.read_file;
            po.shorten = sched::PipelineOptions::Shorten::Always; // the kernels' runs are short
            if (alternative) {
                po.max_ii_search = kAlternativeIiSearch;
                po.max_unscheduled_iis = kAlternativeUnscheduled;
            }
            const sched::PipelineResult pr2 = sched::pipeline_source(sched::restore_region(around, src), name, m, po);
            around = pr2.pipelined;
            // Each loop named by its line in the .pk (the scheduled text around it has fewer lines).
            const std::vector<int> lines = sched::region_lines(src, name, m);
            b.loop_report = with_source_lines(pr2.report, lines);
            for (std::size_t k = 0; k < pr2.loops.size(); ++k) {
                const sched::LoopSummary& l = pr2.loops[k];
                b.loops.push_back({k < lines.size() ? lines[k] : l.line, l.is_while, l.ii, l.mii, l.stages, l.unroll, l.rec_mii,
                                   l.iteration_cycles, l.iteration_lower});
            }
        }
        const sched::Legalized packed = sched::legalize(around, name, assembles);
        out.text = packed.text;
        b.scheduled = true;
        b.blocks = static_cast<int>(pr.blocks.size());
        b.blocks_shortest = static_cast<int>(std::count_if(pr.blocks.begin(), pr.blocks.end(), [](const sched::BlockStats& s) { return s.shortest; }));
        b.nops = hand.nops + region_nops + packed.nops;
    } catch (const base::Error& e) {
        throw std::runtime_error(name + " (" + sources.origin + ") does not assemble for machine '" + m.name + "' (" +
                                 m.source + "):\n" + sched::CopiedLines(sources.text(pk), name).named(e.what()));
    }
    return out;
}

// schedule_source through the disk cache (kbuild/schedule_cache.hpp): an alternative that did not
// schedule is kept as its error, to be thrown again.
Scheduled cached_schedule_source(const kernels::SourceSet& sources, const std::string& pk, const isa::Machine& m,
                                 const assembler::AsmOptions& opts, bool alternative) {
    const std::string key = schedule_key(sources, pk, m) + "/" + m.name + (alternative ? "/alternative" : "/main");
    if (std::optional<detail::StoredSchedule> hit = detail::load_schedule(key)) {
        if (!hit->error.empty()) throw std::runtime_error(hit->error);
        return {hit->text, hit->build, hit->name};
    }
    try {
        Scheduled out = schedule_source(sources, pk, m, opts, alternative);
        detail::store_schedule(key, {out.text, out.name, "", out.build});
        return out;
    } catch (const std::runtime_error& e) {
        if (alternative) detail::store_schedule(key, {"", "", e.what(), {}});
        throw;
    }
}

// Whether m has p's latencies, branch penalty and memories, and at least its registers, ports and
// slots (each of p's slots matched to one of m's that accepts every class it does).
bool at_least(const isa::Machine& m, const isa::Machine& p) {
    if (m.latency != p.latency || m.branch_penalty != p.branch_penalty || m.memories != p.memories) return false;
    for (std::size_t f = 0; f < m.regs.size(); ++f)
        if (m.regs[f].count < p.regs[f].count || m.regs[f].read_ports < p.regs[f].read_ports ||
            m.regs[f].write_ports < p.regs[f].write_ports)
            return false;
    std::vector<bool> used(m.slots.size());
    for (const isa::SlotDesc& ps : p.slots) { // the narrowest of m's that covers it
        int best = -1;
        for (std::size_t k = 0; k < m.slots.size(); ++k)
            if (!used[k] && (m.slots[k].classes & ps.classes) == ps.classes &&
                (best < 0 || std::popcount(m.slots[k].classes) < std::popcount(m.slots[static_cast<std::size_t>(best)].classes)))
                best = static_cast<int>(k);
        if (best < 0) return false;
        used[static_cast<std::size_t>(best)] = true;
    }
    return true;
}

// The first error of a diagnostic, without its location: "no modulo schedule found for ...".
std::string first_error(const std::string& diagnostics) {
    const std::size_t at = diagnostics.find("error: ");
    std::string line = diagnostics.substr(at == std::string::npos ? 0 : at + 7);
    return line.substr(0, line.find('\n'));
}

// The sources of kernel `path` ("ic/intersect.s") before scheduling: "ic/intersect.pk", then its
// alternatives "ic/intersect.<variant>.pk" in name order.
std::vector<std::string> candidate_sources(const kernels::SourceSet& sources, const std::string& path) {
    const std::string stem = path.substr(0, path.rfind('.'));
    std::vector<std::string> out = {stem + ".pk"};
    std::vector<std::string> variants;
    for (const kernels::SourceFile& f : sources.files)
        if (f.path.size() > stem.size() + 4 && f.path.compare(0, stem.size() + 1, stem + ".") == 0 &&
            f.path.compare(f.path.size() - 3, 3, ".pk") == 0 && f.path != out[0])
            variants.push_back(f.path);
    std::sort(variants.begin(), variants.end());
    out.insert(out.end(), variants.begin(), variants.end());
    return out;
}

// A kernel scheduled (or kept) for a machine, measured on the kernel report's workloads.
struct Candidate {
    Scheduled s;
    std::shared_ptr<const iss::Program> prog;
    std::string what;    // as the one chosen
    std::string against; // as one not chosen, after its cycles
    std::uint64_t cycles = 0; // on the kernel workloads, once measured
    bool measured = false;
    bool main = false;  // the committed kernel or the main source's: a dispatch kernel a hybrid can start from
    std::string origin; // the preset it was scheduled for, where not for this machine
};

// The list lengths from which a hybrid kernel runs a list through its loops, one candidate each:
// on long-latency machines the best is 4-16 references, by scene (rings: none).
constexpr std::uint32_t kLongListsFrom[] = {4, 8, 16};

// `dispatch` (the main source's kernel) joined with `loops` (an alternative's) into the hybrid
// kernels (hybrid_kernel.hpp), its joins legalized for m once, one for each list length of
// kLongListsFrom. Named "kernels/ic/intersect.pk+intersect.loops.pk" (a name in the sources'
// folder, for its .include). Throws std::runtime_error when the join is refused or does not
// assemble.
std::vector<Candidate> hybrid_candidates(const Candidate& dispatch, const Candidate& loops, const std::string& joined,
                                         const isa::Machine& m, const assembler::AsmOptions& opts) {
    const std::string name = dispatch.s.name + "+" + loops.s.name.substr(loops.s.name.rfind('/') + 1);
    const auto assembles = assembles_as(name, m, opts);
    sched::Legalized legal;
    try {
        legal = sched::legalize(joined, name, assembles);
    } catch (const base::Error& e) {
        throw std::runtime_error(e.what());
    }
    std::vector<Candidate> out;
    for (std::uint32_t from : kLongListsFrom) {
        Candidate k;
        k.s.name = name;
        k.s.text = detail::with_long_from(legal.text, from);
        const assembler::AsmResult g = assembler::assemble_string(k.s.text, name, m, opts);
        if (!g.ok) throw std::runtime_error(g.diagnostics);
        KernelBuild& b = k.s.build;
        b = loops.s.build; // its loops
        b.machine = m.name;
        b.scheduled = dispatch.s.build.scheduled || loops.s.build.scheduled;
        b.blocks = dispatch.s.build.blocks + loops.s.build.blocks;
        b.blocks_shortest = dispatch.s.build.blocks_shortest + loops.s.build.blocks_shortest;
        b.nops = dispatch.s.build.nops + loops.s.build.nops + legal.nops;
        k.prog = iss::load_program(g.object, m);
        k.origin = dispatch.origin;
        k.what = fmt::format("{}, with {} for lists of {} or more", dispatch.what, loops.what, from);
        k.against = fmt::format("{} with the loops for lists of {} or more", dispatch.against, from);
        out.push_back(std::move(k));
    }
    return out;
}

// Every candidate kernel for m: the committed kernel where it is legal on m as written (its preset,
// or a machine with more resources and the same latencies), then each source scheduled for m (for
// the preset, its alternatives only), then the presets' kernels m can run as written, then the
// hybrids (hybrid_kernel.hpp) of each of those machines' fastest dispatch kernel and its loops;
// `dropped` says which alternatives or hybrids did not schedule or assemble, and why. With more
// than one, each is measured on the kernel workloads.
struct Candidates {
    std::vector<Candidate> all;
    std::vector<std::string> dropped;
    std::optional<Scheduled> failed; // the main source did not assemble: assemble_kernel reports it
};

Candidates candidates_for(const kernels::SourceSet& sources, const std::string& path, const isa::Machine& m,
                          const assembler::AsmOptions& opts) {
    Candidates out;
    std::vector<Candidate>& all = out.all;
    const std::string committed = sources.text(path);
    // A preset's committed kernel is its main source scheduled for it (kernels.regenerate holds
    // them equal): only the alternatives are scheduled beside it.
    const bool preset = scheduled_for(committed, m);
    if (const assembler::AsmResult c = assembler::assemble_string(committed, kPrefix + path, m, opts); !c.ok && preset) {
        out.failed = Scheduled{committed, {}, kPrefix + path}; // assemble_kernel reports its diagnostics
        out.failed->build.machine = m.name;
        return out;
    } else if (c.ok) {
        Candidate k;
        k.s.text = committed;
        k.s.name = kPrefix + path;
        k.s.build.machine = m.name;
        k.prog = iss::load_program(c.object, m);
        k.what = fmt::format("the {} kernel as written", assembler::header_machine(committed));
        k.main = true;
        if (!preset) k.origin = assembler::header_machine(committed);
        k.against = "for " + k.what;
        all.push_back(std::move(k));
    }
    const std::vector<std::string> pks = candidate_sources(sources, path);
    // The sources are scheduled side by side (each search is deterministic; the first machine
    // a user describes waits for the longest one, not for their sum).
    std::vector<std::future<Scheduled>> scheduling;
    for (const std::string& pk : pks)
        scheduling.push_back(pk == pks.front() && preset ? std::future<Scheduled>{}
                                                         : std::async(std::launch::async, [&, pk] {
                                                               return cached_schedule_source(sources, pk, m, opts, pk != pks.front());
                                                           }));
    for (std::size_t i = 0; i < pks.size(); ++i) {
        const std::string& pk = pks[i];
        const bool main = pk == pks.front(); // it must schedule and assemble; an alternative may not
        if (main && preset) continue;
        Candidate k;
        try {
            k.s = scheduling[i].get();
        } catch (const std::runtime_error& e) {
            if (main) throw;
            out.dropped.push_back(pk + " not scheduled (" + first_error(e.what()) + ")");
            continue;
        }
        const assembler::AsmResult g = assembler::assemble_string(k.s.text, k.s.name, m, opts);
        if (!g.ok) {
            if (main) {
                out.failed = k.s;
                return out;
            }
            out.dropped.push_back(pk + " not assembled (" + first_error(g.diagnostics) + ")");
            continue;
        }
        k.prog = iss::load_program(g.object, m);
        k.what = main ? "scheduled for this machine" : pk + " scheduled for this machine";
        k.main = main;
        k.against = k.what;
        all.push_back(std::move(k));
    }
    // A machine with the latencies of a preset and at least its resources can run that preset's
    // kernels as written: they are candidates too, so that the search finding less for the bigger
    // machine never makes it slower (ic-real with a second IU, whose loops got schedules of fewer
    // stages but longer iterations than ic-real's). A preset's committed kernel is the first
    // candidate above.
    for (const isa::Machine& p : detail::presets())
        if (!p.same_as(m) && at_least(m, p))
            for (const std::string& pk : pks) {
                if (pk == pks.front() && scheduled_for(committed, p)) continue; // the committed kernel, above
                Candidate k;
                try {
                    k.s = cached_schedule_source(sources, pk, p, opts, pk != pks.front());
                } catch (const std::runtime_error&) {
                    continue;
                }
                const assembler::AsmResult g = assembler::assemble_string(k.s.text, k.s.name, m, opts);
                if (!g.ok) continue;
                k.s.build.machine = m.name;
                k.prog = iss::load_program(g.object, m);
                k.what = fmt::format("{} scheduled for {}", pk, p.name);
                k.against = k.what;
                k.main = pk == pks.front();
                k.origin = p.name;
                all.push_back(std::move(k));
            }
    auto measure = [&](Candidate& k) {
        if (k.measured) return;
        k.measured = true;
        try {
            k.cycles = workload_busy_cycles(k.prog, path);
        } catch (const iss::LoadError& e) { // the workloads' data need the memory a scene's would
            throw iss::LoadError(fmt::format("machine '{}' ({}): measuring the {} candidates on their workloads: {} (a "
                                             "scene's data need as much)",
                                             m.name, m.source, path, e.message()));
        }
    };
    // Per machine the kernels were scheduled for (this one, a preset it is at least), the fastest
    // dispatch kernel (the committed one or the main source's) joined with each alternative that
    // says how (its `hybrid_start`): its bodies for short lists, the alternative's loops for long
    // ones.
    const std::size_t n = all.size();
    if (n > 1)
        for (Candidate& k : all)
            if (k.main) measure(k);
    std::map<std::string, std::size_t> dispatch; // origin -> its fastest main candidate
    for (std::size_t d = 0; d < n; ++d)
        if (all[d].main) {
            const auto [at, fresh] = dispatch.emplace(all[d].origin, d);
            if (!fresh && all[d].cycles < all[at->second].cycles) at->second = d;
        }
    for (std::size_t l = 0; l < n; ++l) {
        const auto d = dispatch.find(all[l].origin);
        if (all[l].main || d == dispatch.end()) continue;
        const Candidate& k = all[d->second];
        const detail::HybridText joined = detail::hybrid_kernel_text(k.s.text, all[l].s.text, kLongListsFrom[0]);
        std::string why = joined.why;
        if (joined.text) try {
                for (Candidate& h : hybrid_candidates(k, all[l], *joined.text, m, opts)) all.push_back(std::move(h));
            } catch (const std::runtime_error& e) {
                why = "not assembled: " + first_error(e.what());
            }
        if (!why.empty()) out.dropped.push_back(fmt::format("the hybrid of {} and {} ({})", k.what, all[l].what, why));
    }
    if (all.size() > 1)
        for (Candidate& k : all) measure(k);
    return out;
}

// The candidate busy for the fewest cycles (the first on a tie: the committed kernel, then the
// sources in candidate_sources order): on the scene's sampled visits when there is a sample, else
// on the kernel workloads. Its build says which it is and what the others cost.
Scheduled choose(const Candidates& c, const LazySceneSample* scene) {
    if (c.failed) return *c.failed;
    const std::vector<Candidate>& all = c.all;
    if (all.empty()) throw std::logic_error("choose: no candidate kernel"); // the main source or the committed one is one
    if (all.size() == 1) {
        Scheduled out = all[0].s;
        if (!c.dropped.empty()) out.build.choice = fmt::format("{}: {}", all[0].what, fmt::join(c.dropped, "; "));
        return out;
    }
    std::vector<std::uint64_t> cycles;
    for (const Candidate& k : all) cycles.push_back(scene ? sample_busy_cycles(k.prog, scene->get()) : k.cycles);
    const std::size_t best = static_cast<std::size_t>(std::min_element(cycles.begin(), cycles.end()) - cycles.begin());
    auto others = [&](const std::vector<std::uint64_t>& n) {
        std::string o;
        for (std::size_t i = 0; i < all.size(); ++i)
            if (i != best) o += fmt::format("{}{} {}", o.empty() ? "" : ", ", n[i], all[i].against);
        return o;
    };
    std::string why;
    if (scene) {
        std::vector<std::uint64_t> workloads;
        for (const Candidate& k : all) workloads.push_back(k.cycles);
        why = fmt::format("{} busy cycles on this scene's sample ({}) against {}; on the kernel workloads {} against {}",
                          cycles[best], scene->get().what(), others(cycles), workloads[best], others(workloads));
    } else {
        why = fmt::format("{} busy cycles on the kernel workloads against {}", cycles[best], others(cycles));
    }
    for (const std::string& d : c.dropped) why += "; " + d;
    Scheduled out = all[best].s;
    out.build.choice = fmt::format("{}: {}", all[best].what, why);
    out.build.candidates = static_cast<int>(all.size());
    return out;
}
} // namespace

namespace {
// A kernel's .include "../abi.inc" (and any other) resolves inside `sources`.
assembler::AsmOptions kernel_asm_options(const kernels::SourceSet& sources) {
    assembler::AsmOptions opts;
    opts.read_file = [&sources](const std::string& p, std::string& text) {
        if (p.compare(0, kPrefix.size(), kPrefix) != 0 || !sources.has(p.substr(kPrefix.size()))) return false;
        text = sources.text(p.substr(kPrefix.size()));
        return true;
    };
    return opts;
}
} // namespace

std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const isa::Machine& given, KernelBuild* build, const LazySceneSample* scene) {
    const isa::Machine& m = canonical(given);
    KernelBuild b;
    b.machine = m.name;
    const assembler::AsmOptions opts = kernel_asm_options(sources);
    std::string text = sources.text(path);
    std::string name = kPrefix + path;
    const std::string pk = path.substr(0, path.rfind('.')) + ".pk";
    // Another machine: schedule its sources for m. A preset rendering a scene: weigh its committed
    // kernel against the alternatives scheduled for it (ic/intersect.loops.pk wins on long voxel
    // lists); without a scene (the kernel report, the build's compiled runs) it is the committed one.
    const bool preset = scheduled_for(text, m);
    if (sources.has(pk) && (!preset || (scene && candidate_sources(sources, path).size() > 1))) {
        const std::string key = schedule_key(sources, path, m);
        std::shared_ptr<const Candidates> found;
        {
            std::lock_guard lock(schedule_mutex);
            if (const auto hit = schedule_cache().find(key); hit != schedule_cache().end()) found = hit->second;
        }
        if (!found) { // cells schedule different kernels at once; a rare duplicate is harmless
            found = std::make_shared<const Candidates>(candidates_for(sources, path, m, opts));
            std::lock_guard lock(schedule_mutex);
            schedule_cache().emplace(key, found);
        }
        const Scheduled chosen = choose(*found, scene);
        text = chosen.text;
        b = chosen.build;
        name = chosen.name;
    }
    b.source = name;
    if (build) *build = b;
    assembler::AsmResult r = assembler::assemble_string(text, name, m, opts);
    if (!r.ok)
        throw std::runtime_error(name + " (" + sources.origin + ") does not assemble for machine '" + m.name +
                                 "' (" + m.source + "):\n" + r.diagnostics);
    return iss::load_program(r.object, m);
}

std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const std::string& machine) {
    return assemble_kernel(sources, path, isa::load_machine(machine));
}

std::shared_ptr<const iss::Program> assemble_source(const kernels::SourceSet& sources, const std::string& pk,
                                                    const std::string& machine) {
    const isa::Machine loaded = isa::load_machine(machine);
    const isa::Machine& m = canonical(loaded);
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const iss::Program>> built; // tests ask for one several times
    const std::string key = schedule_key(sources, pk, m);
    {
        std::lock_guard lock(mutex);
        if (const auto hit = built.find(key); hit != built.end()) return hit->second;
    }
    const assembler::AsmOptions opts = kernel_asm_options(sources);
    const std::string stem = pk.substr(0, pk.find('.', pk.rfind('/') + 1));
    const Scheduled s = cached_schedule_source(sources, pk, m, opts, pk != stem + ".pk");
    const assembler::AsmResult r = assembler::assemble_string(s.text, s.name, m, opts);
    if (!r.ok) throw std::runtime_error(s.name + " does not assemble for machine '" + m.name + "':\n" + r.diagnostics);
    std::shared_ptr<const iss::Program> prog = iss::load_program(r.object, m);
    std::lock_guard lock(mutex);
    built.emplace(key, prog);
    return prog;
}

kernels::ListLayout list_layout(const iss::Program& p) {
    kernels::ListLayout out;
    out.by_kind = p.find_symbol(kernels::abi::kListsByKindLabel) != nullptr;
    for (const isa::Symbol& s : p.object().symbols) {
        if (s.kind != isa::SymbolKind::Code || !s.name.starts_with(kernels::abi::kListsLongPrefix)) continue;
        const std::string_view n = std::string_view(s.name).substr(kernels::abi::kListsLongPrefix.size());
        std::uint32_t from = 0;
        const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), from);
        if (ec != std::errc() || end != n.data() + n.size() || from == 0 || (out.long_from && out.long_from != from) || out.by_kind)
            throw std::runtime_error(fmt::format("the IC kernel's label '{}' asks for no layout the host knows (one label "
                                                 "{}N with N > 0, and not {} too)",
                                                 s.name, kernels::abi::kListsLongPrefix, kernels::abi::kListsByKindLabel));
        out.long_from = from;
    }
    return out;
}

KernelRunner::KernelRunner(std::shared_ptr<const iss::Program> program, iss::Engine engine)
    : prog(std::move(program)), proc(std::make_unique<iss::Processor>(prog, engine)) {
    // out1 and out2 serve an OS kernel and an IC kernel alike: both send on channels 1 and 2.
    static_assert(kernels::abi::kChOsIc == kernels::abi::kChIcOs && kernels::abi::kChOsSc == kernels::abi::kChIcSc);
    proc->attach_channel(kernels::abi::kChIn, &in);
    proc->attach_channel(kernels::abi::kChOsIc, &out1);
    proc->attach_channel(kernels::abi::kChOsSc, &out2);
}

void KernelRunner::run(std::uint64_t max_cycles) {
    const iss::Status s = proc->run(max_cycles);
    if (s != iss::Status::Blocked || proc->blocked_channel() != 0)
        throw std::runtime_error("kernel did not wait for input: " + proc->fault_report());
}

} // namespace nesshi::kbuild
