// `nesshi render`: render a scene with a chosen model (native or the machine's S, M, V) to PNG, stats and buffers.
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "stage_machines.hpp"
#include "outputs.hpp"
#include "ranges.hpp"

#include "base/progress.hpp"
#include "base/write_file.hpp"

#include "machine/memory_report.hpp"
#include "machine/kernel_report.hpp"
#include "machine/machine.hpp"
#include "iss/stats.hpp"
#include "kernels/abi.hpp"
#include "rt/render.hpp"

#include <fmt/format.h>

#include <charconv>
#include <climits>
#include <cstdio>
#include <functional>
#include <map>
#include <unistd.h>

namespace nesshi::cli {

namespace {

struct RenderArgs {
    std::string scene;
    std::string model = "native";
    std::string size = "512";
    std::string grid = "50";
    int threads = 0;
    std::string out, stats_json, id_buffer, t_buffer;
    double cutoff = 0;
    bool quiet = false;
    bool detail = false; // the OS's and IC's processor statistics after the summary
    // the simulated machine (models S, M, V)
    machine::Options mo;
    StageMachineNames machines; // loaded into mo's when the command runs
    bool cache = false;
    std::string balance = "interleaved";
    // For checking combinations: every option of the machine group, and the ones that need another.
    std::vector<const CLI::Option*> machine_only;
    std::vector<const CLI::Option*> cache_params; // --cache-size, --cache-ways, --cache-line, --miss-cycles
    const CLI::Option *epoch = nullptr, *fifo_latency = nullptr, *quantum = nullptr, *no_resident = nullptr;
    const CLI::Option *window = nullptr, *ray_slots = nullptr, *size_opt = nullptr;
};

const char* const kModels = "native, S, M, V";

// A positive integer of --size or --grid; `words` says what is allowed.
int parse_int(const std::string& s, const char* what, int max, const char* words) {
    int v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v < 1 || v > max)
        throw UsageError(fmt::format("bad {} '{}' ({})", what, s, words));
    return v;
}

constexpr const char* kSizeWords = "--size is W or WxH, each an integer between 1 and 16384";

// Options that would be silently ignored are errors: machine options with --model native, and
// options without the one that gives them a meaning.
void check_combinations(const RenderArgs& a, bool native, machine::Model model) {
    auto given = [](const CLI::Option* o) { return o && o->count() > 0; };
    if (native)
        for (const CLI::Option* o : a.machine_only)
            if (given(o))
                throw UsageError(fmt::format("{} needs --model S, M or V (the simulated machine); --model native "
                                                     "is the C++ tracer",
                                                     o->get_name()));
    for (const CLI::Option* o : a.cache_params)
        if (given(o) && !a.cache)
            throw UsageError(
                fmt::format("{} needs --cache (without it the IC cache is ideal: every access hits)", o->get_name()));
    if (given(a.no_resident) && !a.cache)
        throw UsageError("--no-resident needs --cache (with the ideal cache global memory costs what resident "
                                 "memory does, so it would change nothing)");
    if (given(a.epoch) && a.balance != "dynamic") throw UsageError("--epoch needs --balance dynamic");
    if (model == machine::Model::S)
        for (const CLI::Option* o : {a.fifo_latency, a.quantum})
            if (given(o))
                throw UsageError(fmt::format(
                    "{} has no effect on model S (one processor runs the three stages on one clock)", o->get_name()));
}

void run_render(const RenderArgs& a) {
    const bool native = a.model == "native";
    machine::Options mo = a.mo;
    mo.resident = a.no_resident->count() == 0;
    if (!native && !machine::parse_model(a.model, mo.model))
        throw UsageError(fmt::format("unknown model '{}' (available: {})", a.model, kModels));
    check_combinations(a, native, mo.model);
    a.machines.load(mo);
    // One output may be stdout ('-'); the report then goes to stderr.
    const bool output_on_stdout = stdout_output({{"-o", a.out}, {"--stats-json", a.stats_json}, {"--id-buffer", a.id_buffer},
                                                 {"--t-buffer", a.t_buffer}, {"--trace", mo.trace_json}});
    std::FILE* report = output_on_stdout ? stderr : stdout;
    check_outputs({a.out, a.stats_json, a.id_buffer, a.t_buffer, mo.trace_json, mo.timeline_svg});
    // Bounded FIFOs without a chosen window: limit the rays in flight so that no FIFO can fill
    // (machine::Options::ray_slots); the window alone bounds corners, and small FIFOs deadlock.
    const bool auto_slots = mo.fifo_capacity > 0 && a.window->count() == 0 && a.ray_slots->count() == 0;
    if (auto_slots) mo.ray_slots = machine::deadlock_free_ray_slots(mo.fifo_capacity);
    mo.cache.enabled = a.cache;
    mo.dynamic_balance = a.balance == "dynamic";
    rt::RenderOptions opt;
    if (auto x = a.size.find('x'); x != std::string::npos) {
        opt.width = parse_int(a.size.substr(0, x), "width", 16384, kSizeWords);
        opt.height = parse_int(a.size.substr(x + 1), "height", 16384, kSizeWords);
    } else {
        opt.width = opt.height = parse_int(a.size, "size", 16384, kSizeWords);
    }
    int grid = a.grid == "auto" ? 0 : parse_int(a.grid, "grid resolution", INT_MAX, "--grid is 'auto' or an integer from 1");
    try {
        rt::check_grid_resolution(grid); // the one limit, shared with scene info
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    opt.threads = a.threads;
    mo.threads = a.threads;
    opt.cutoff = a.cutoff;
    opt.id_buffer = !a.id_buffer.empty();
    opt.t_buffer = !a.t_buffer.empty();
    const bool tty = isatty(STDERR_FILENO) && !a.quiet;
    const base::ProgressBar bar(stderr);
    if (tty) {
        opt.progress = [bar](int done, int total) { bar(static_cast<std::uint64_t>(done), static_cast<std::uint64_t>(total)); };
        mo.progress = bar;
    }

    rt::Scene scene = rt::load_scene(a.scene);
    if (a.size_opt->count() == 0) { // the file's resolution (512 x 512 when it names none)
        opt.width = scene.view.width;
        opt.height = scene.view.height;
    }
    rt::PreparedScene prep = rt::prepare(std::move(scene), grid);
    machine::Result mr;
    if (native) {
        mr.render = rt::render_native(prep, opt);
    } else {
        if (!a.quiet) status("{}", machine::schedules_used(mo));
        mr = machine::render(prep, opt, mo);
    }
    const rt::RenderResult& r = mr.render;

    if (!a.out.empty()) rt::write_png(a.out, r.image);
    if (opt.id_buffer) rt::write_id_buffer(a.id_buffer, r.id_buffer);
    if (opt.t_buffer) rt::write_t_buffer(a.t_buffer, r.t_buffer);
    if (!a.stats_json.empty())
        base::write_file(a.stats_json, rt::stats_text(native ? machine::with_memory_report(rt::stats_json(prep, opt, r, a.model),
                                                                                           prep.grid, prep.shapes.shapes.size())
                                                             : machine::stats_json(prep, opt, mo, mr)));
    if (!a.quiet) {
        fmt::print(report, "{} {}x{} model {} (SPD mode: depth {}, corner rays{})\n", prep.scene.name, opt.width, opt.height,
                   a.model, opt.max_depth, opt.cutoff > 0 ? fmt::format(", cut-off {:g}", opt.cutoff) : "");
        fmt::print(report, "{}", rt::format_grid(prep.grid) +
                             (native ? machine::memory_report(prep.grid, prep.shapes.shapes.size())
                                     : machine::memory_report(prep.grid, prep.shapes.shapes.size(), mo)).text());
        if (native) {
            fmt::print(report, "{}", rt::format_rays(r.stats));
        } else {
            fmt::print(report, "{}", rt::format_rays(r.stats, {.tracer = false}));
            if (auto_slots)
                fmt::print(report, "ray slots {}: at most {} rays in flight ({} words per FIFO / {}, a ray's longest message), "
                           "so no FIFO fills (--ray-slots or --window to choose)\n",
                           mo.ray_slots, mo.ray_slots, mo.fifo_capacity, machine::kLongestMessageWords);
            fmt::print(report, "{}", machine::format_stats(mr.machine));
            fmt::print(report, "SC is modelled (counted operations x seq latencies), OS and IC are simulated.\n");
            if (a.detail) {
                const char* over = mr.machine.per_pe.size() > 1 ? ", summed over PEs" : "";
                fmt::print(report, "\n--- OS stage{} ---\n{}", over, iss::stats_text(mr.machine.os_detail));
                fmt::print(report, "\n--- IC stage{} ---\n{}", over, iss::stats_text(mr.machine.ic_detail));
            }
        }
    }
}

} // namespace

void add_render(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "Render a scene (NFF file or built-in SPD name) to PNG");
    auto a = std::make_shared<RenderArgs>();
    cmd->add_option("scene", a->scene, "NFF file or built-in name (balls mount rings tetra tree gears, NAME:SIZE)")->required();
    cmd->add_option("--model", a->model, "native (C++ tracer, the default), V (VLIW OS + IC), M (sequential pipeline), S (one sequential processor)");
    cmd->add_option("--size", a->size, "image size W or WxH (default: the scene file's resolution, else 512)");
    cmd->add_option("--grid", a->grid, "voxels per axis, or 'auto' (default 50)");
    cmd->add_option("--threads", a->threads, "host threads (default: all cores); never changes the cycles")->check(between(0, 1024));
    cmd->add_option("-o,--output", a->out, "PNG image ('-': stdout; this or one other output, and the report goes to stderr)");
    cmd->add_option("--stats-json", a->stats_json, "statistics as JSON ('-': stdout)");
    cmd->add_option("--id-buffer", a->id_buffer, "eye-ray primitive ids: raw int32 LE, (H+1) x (W+1) ('-': stdout)");
    cmd->add_option("--t-buffer", a->t_buffer, "eye-ray hit distances: raw float32 LE, (H+1) x (W+1) ('-': stdout)");
    cmd->add_option("--cutoff", a->cutoff, "contribution cut-off for secondary rays (0 = off, SPD mode)")
        ->check(between(0.0, 1.0));
    cmd->add_flag("-q,--quiet", a->quiet, "no report, no progress bar");
    auto* m = "Machine (models S, M, V)";
    cmd->add_option("--pes", a->mo.pes, "processing elements (default 1)")->check(between(1, 64))->group(m);
    cmd->add_option("--balance", a->balance, "DIS: interleaved (corner k to PE k mod N, default) or dynamic")
        ->check(CLI::IsMember({"interleaved", "dynamic"}))->group(m);
    cmd->add_option("--epoch", a->mo.epoch, "dynamic balancing: cycles between DIS hand-outs (default 20000)")
        ->check(between<std::uint64_t>(1, 1'000'000'000))->group(m);
    cmd->add_option("--window", a->mo.window, "eye rays in flight per PE, the DIS's limit (default 64)")
        ->check(between(1, 1 << 20))->group(m);
    cmd->add_option("--fifo-capacity", a->mo.fifo_capacity,
                    "words per FIFO, 0 = unbounded (default); without --window it also sets --ray-slots to capacity/12, "
                    "which cannot deadlock")
        ->check(between<std::size_t>(0, std::size_t{1} << 28))
        ->group(m);
    cmd->add_option("--ray-slots", a->mo.ray_slots,
                    fmt::format("rays in flight per PE (default {}, the OS's ray state table); at most capacity/{} never "
                                "fills a FIFO", kernels::abi::kOsSlots, machine::kLongestMessageWords))
        ->check(between(1, static_cast<int>(kernels::abi::kOsSlots)))
        ->group(m);
    cmd->add_option("--fifo-latency", a->mo.fifo_latency, "extra cycles per FIFO hop (default 0)")
        ->check(between<std::uint32_t>(0, 1'000'000))->group(m);
    cmd->add_flag("--cache", a->cache, "a real IC cache over global memory instead of 100% hits")->group(m);
    cmd->add_option("--cache-size", a->mo.cache.bytes, "IC cache bytes (default 1 MiB)")
        ->check(between<std::uint32_t>(16, 1u << 30))->group(m);
    cmd->add_option("--cache-ways", a->mo.cache.ways, "IC cache ways (default 4)")->check(between<std::uint32_t>(1, 1024))->group(m);
    cmd->add_option("--cache-line", a->mo.cache.line, "IC cache line bytes (default 32)")
        ->check(between<std::uint32_t>(4, 4096))->group(m);
    cmd->add_option("--miss-cycles", a->mo.cache.miss_cycles, "IC cache miss penalty (default 20)")
        ->check(between<std::uint32_t>(0, 1'000'000))->group(m);
    cmd->add_flag("--no-resident")
        ->description("all IC data in global memory (default: as much as fits in resident memory, the most-referenced records first)")
        ->group(m);
    cmd->add_option("--quantum", a->mo.quantum,
                    fmt::format("cycles a stage may run past its turn before the host switches stages (default {}, {} with "
                                "--trace-json or --timeline-svg; performance only, no result depends on it)",
                                machine::Options::kQuantum, machine::Options::kTracedQuantum))
        ->check(between<std::uint64_t>(1, 1'000'000))->group(m);
    cmd->add_option("--max-cycles", a->mo.max_cycles, "stop with an error past this many cycles per PE (default 0: no limit)")
        ->check(between<std::uint64_t>(0, UINT64_MAX))->group(m);
    cmd->add_flag("--detail", a->detail, "also print the OS's and IC's processor statistics (units, ports, ILP histogram, regions)")
        ->group(m);
    cmd->add_flag("--checked", a->mo.checked, "ISS checked engine (ports and hazards checked dynamically)")->group(m);
    cmd->add_option("--trace,--trace-json", a->mo.trace_json,
                    "Chrome/Perfetto trace (JSON) of stage activity and FIFO words; --trace as `sim` names it")
        ->group(m);
    cmd->add_option("--timeline-svg", a->mo.timeline_svg, "the run as a picture (SVG): each stage's busy fraction and each FIFO's "
                                                          "words over time")
        ->group(m);
    cmd->add_option("--kernels", a->mo.kernels_dir, "kernel source folder (default: built in)")->group(m);
    add_stage_machine_options(cmd, a->machines, m);
    for (const CLI::Option* o : cmd->get_options())
        if (o->get_group() == m) a->machine_only.push_back(o);
    for (const char* name : {"--cache-size", "--cache-ways", "--cache-line", "--miss-cycles"})
        a->cache_params.push_back(cmd->get_option(name));
    a->epoch = cmd->get_option("--epoch");
    a->fifo_latency = cmd->get_option("--fifo-latency");
    a->quantum = cmd->get_option("--quantum");
    a->no_resident = cmd->get_option("--no-resident");
    a->window = cmd->get_option("--window");
    a->ray_slots = cmd->get_option("--ray-slots");
    a->size_opt = cmd->get_option("--size");
    cmd->callback([a] {
        run_render(*a);
    });
}

} // namespace nesshi::cli
