// `nesshi demo` (what `make demo` runs): render an SPD scene through the simulated machine
// (model V: the VLIW OS and IC kernels on the ISS, SC modelled), write the PNG, print the
// machine's statistics, and check the image against the native C++ tracer.
// `nesshi demo --isa`: assemble the bundled examples, run each with the checked engine, print ILP.
#include "status.hpp"
#include "commands.hpp"
#include "stage_machines.hpp"

#include "base/progress.hpp"
#include "outputs.hpp"
#include "ranges.hpp"
#include "sim_load.hpp"

#include "iss/processor.hpp"
#include "iss/stats.hpp"
#include "machine/kernel_report.hpp"
#include "machine/machine.hpp"
#include "machine/memory_report.hpp"
#include "rt/render.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <unistd.h>

namespace nesshi::cli {

namespace {
namespace fs = std::filesystem;

// An installed tool's examples (PREFIX/share/nesshisen/examples beside PREFIX/bin/nesshi), else
// those of the source tree it was built from (NESSHI_EXAMPLES_DIR); --examples names another folder.
fs::path default_examples_dir() {
    std::error_code ec;
    const fs::path installed = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path() / "share/nesshisen/examples";
    if (!ec && fs::is_directory(installed, ec)) return installed;
    return fs::path(NESSHI_EXAMPLES_DIR);
}

std::vector<std::string> file_names(const std::vector<fs::path>& files) {
    std::vector<std::string> names;
    for (const fs::path& f : files) names.push_back(f.filename().string());
    return names;
}

void run_demo(const std::string& dir_opt, const std::string& main_example) {
    fs::path dir = dir_opt.empty() ? default_examples_dir() : fs::path(dir_opt);
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".s") files.push_back(e.path());
    if (ec || files.empty())
        throw base::Error(fmt::format("no examples found in {} (use --examples DIR)", dir.string()));
    std::sort(files.begin(), files.end());
    // --detail names an example that is not there: an error, not a table without its detail.
    if (std::none_of(files.begin(), files.end(), [&](const fs::path& f) { return f.filename() == main_example; }))
        throw UsageError(fmt::format("--detail {}: no such example in {} (the .s files there: {})", main_example,
                                     dir.string(), fmt::join(file_names(files), " ")));

    fmt::print("Nesshisen ISS demo: the bundled examples on their machines (checked engine)\n\n");
    fmt::print("{:<22} {:<5} {:>7} {:>8} {:>5} {:>6} {:>6}  {}\n", "example", "mach", "cycles", "bundles", "ops",
               "ILP", "util", "result");
    std::shared_ptr<const iss::Program> main_prog;
    std::unique_ptr<iss::Processor> main_proc;
    for (const fs::path& f : files) {
        auto prog = load_sim_input(f.string(), "");
        auto p = std::make_unique<iss::Processor>(prog, iss::Engine::Checked);
        // FIFO examples get a small input: a count and three words.
        iss::QueueChannel in, out;
        for (uint32_t w : {3u, 10u, 20u, 30u}) in.feed(w);
        in.close();
        for (const auto& d : prog->ops()) {
            auto k = d.instr.info().kind;
            if (k == isa::Kind::Recv) p->attach_channel(d.imm, &in);
            if (k == isa::Kind::Send) p->attach_channel(d.imm, &out);
        }
        iss::Status st = p->run(10'000'000);
        iss::Stats s = iss::compute_stats(*p);
        fmt::print("{:<22} {:<5} {:>7} {:>8} {:>5} {:>6.2f} {:>6.2f}  {}\n", f.filename().string(), s.machine, s.cycles,
                   s.bundles, s.ops, s.ilp, s.utilisation,
                   st == iss::Status::Halted ? "halted" : std::string(iss::status_name(st)));
        if (st == iss::Status::Faulted) fmt::print("{}", p->fault_report());
        if (f.filename() == main_example) main_proc = std::move(p);
    }
    if (main_proc) {
        fmt::print("\n{} in detail (ILP, unit utilisation, port utilisation):\n\n", main_example);
        fmt::print("{}", iss::stats_text(iss::compute_stats(*main_proc)));
    }
}
struct DemoArgs {
    std::string scene = "balls";
    int size = 128;
    std::string out = "nesshi-demo.png";
    bool isa = false;
    std::string examples, detail = "saxpy_pipelined.s";
    StageMachineNames machine_names; // --os-machine, --ic-machine, --seq-machine
};

using base::seconds_since;

void run_machine_demo(const DemoArgs& a) {
    refuse_stdout("-o", a.out, "stdout holds the demo's report (nesshi render --model V -o - writes a PNG there)");
    check_output(a.out);
    fmt::print("Nesshisen demo: SPD '{}' at {}x{} through model V (one PE: OS and IC VLIW kernels on the ISS)\n",
               a.scene, a.size, a.size);
    machine::Options mo;
    a.machine_names.load(mo);
    const StageMachineNames& n = a.machine_names;
    if (!n.os.empty() || !n.ic.empty() || !n.seq.empty())
        fmt::print("machines: OS {}, IC {}, SC prices {}\n", mo.os_machine.reference(), mo.ic_machine.reference(),
                   mo.seq_machine.reference());
    const auto t_prep = std::chrono::steady_clock::now();
    const rt::PreparedScene prep = rt::prepare(rt::load_scene(a.scene), 0); // grid: the paper's pre-pass choice
    fmt::print("{}grid chosen by the low-resolution pre-pass ({:.1f} s)\n",
               rt::format_grid(prep.grid) + machine::memory_report(prep.grid, prep.shapes.shapes.size()).text(), seconds_since(t_prep));
    rt::RenderOptions opt;
    opt.width = opt.height = a.size;
    mo.model = machine::Model::V;
    if (isatty(STDERR_FILENO)) {
        mo.progress = base::ProgressBar(stderr);
    }
    status("{}", machine::schedules_used(mo));
    const machine::Result mr = machine::render(prep, opt, mo);
    rt::write_png(a.out, mr.render.image);
    fmt::print("{}{}", rt::format_rays(mr.render.stats, {.tracer = false}), machine::format_stats(mr.machine));
    fmt::print("SC is modelled (counted operations x seq latencies), OS and IC are simulated.\n");

    const auto t_native = std::chrono::steady_clock::now();
    const rt::RenderResult native = rt::render_native(prep, opt);
    const double native_s = seconds_since(t_native);
    const bool same = native.image.rgb == mr.render.image.rgb && native.stats.rays == mr.render.stats.rays && native.id_buffer == mr.render.id_buffer;
    fmt::print("native C++ tracer: {:.2f} s; image, ID buffer and ray counts {} (simulation {:.0f}x slower)\n", native_s,
               same ? "identical" : "DIFFERENT", mr.machine.wall_seconds / std::max(native_s, 1e-9));
    fmt::print("wrote {}\n", a.out);
    fmt::print("next: nesshi render {} --model M (or S, native) --size 512, nesshi paper --help\n", a.scene);
    if (!same) throw base::Error("the simulated machine and the native tracer disagree");
}

} // namespace

void add_demo(CLI::App& app) {
    auto* cmd = app.add_subcommand("demo", "Render a scene through the simulated machine (model V); --isa: the ISA examples");
    auto a = std::make_shared<DemoArgs>();
    auto* scene = cmd->add_option("--scene", a->scene, "SPD name, NAME:SIZE or NFF file")->capture_default_str();
    auto* size = cmd->add_option("--size", a->size, "image size N x N")->capture_default_str()->check(between(1, 4096));
    auto* out = cmd->add_option("-o,--output", a->out, "PNG image")->capture_default_str();
    auto* isa = cmd->add_flag("--isa", a->isa, "instead: assemble and simulate the bundled examples, print ILP and utilisation");
    // Options of the other demo are errors, not ignored.
    add_stage_machine_options(cmd, a->machine_names);
    isa->excludes(scene)->excludes(size)->excludes(out);
    for (const char* name : {"--os-machine", "--ic-machine", "--seq-machine"}) isa->excludes(cmd->get_option(name));
    cmd->add_option("--examples", a->examples, "with --isa: folder of example .s files (default: examples/)")->needs(isa);
    cmd->add_option("--detail", a->detail, "with --isa: example whose full statistics are printed")
        ->capture_default_str()
        ->needs(isa);
    cmd->callback([a] {
        if (a->isa) {
            run_demo(a->examples, a->detail);
            return;
        }
        run_machine_demo(*a);
    });
}

} // namespace nesshi::cli
