// `nesshi demo` (what `make demo` runs until a full render exists): assemble the bundled
// examples, run each on the simulator with the checked engine, and print their statistics.
#include "commands.hpp"
#include "sim_load.hpp"

#include "iss/processor.hpp"
#include "iss/stats.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>

namespace nesshi::cli {

namespace {
namespace fs = std::filesystem;

// The examples live beside this file's directory in the source tree (cli/../examples); a
// different location can be given with --examples.
fs::path default_examples_dir() { return fs::path(__FILE__).parent_path().parent_path() / "examples"; }

void run_demo(const std::string& dir_opt, const std::string& main_example) {
    fs::path dir = dir_opt.empty() ? default_examples_dir() : fs::path(dir_opt);
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".s") files.push_back(e.path());
    if (ec || files.empty())
        throw CLI::RuntimeError(fmt::format("no examples found in {} (use --examples DIR)", dir.string()), 1);
    std::sort(files.begin(), files.end());

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
} // namespace

void add_demo(CLI::App& app) {
    auto* cmd = app.add_subcommand("demo", "Assemble and simulate the bundled examples; print ILP and utilisation");
    auto dir = std::make_shared<std::string>();
    auto main_example = std::make_shared<std::string>("saxpy_pipelined.s");
    cmd->add_option("--examples", *dir, "Directory of example .s files (default: the source tree's examples/)");
    cmd->add_option("--detail", *main_example, "Example whose full statistics are printed")->capture_default_str();
    cmd->callback([dir, main_example] { run_demo(*dir, *main_example); });
}

} // namespace nesshi::cli
