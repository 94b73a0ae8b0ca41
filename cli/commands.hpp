// Registration of each `nesshi` subcommand; one function per file cmd_*.cpp.
#pragma once
#include <CLI/CLI.hpp>

namespace nesshi::cli {
// Each adds its subcommand to the app; the callback runs it and throws on failure (errors.hpp
// says what each exception means and how it is printed).
void add_asm(CLI::App& app);
void add_dis(CLI::App& app);
void add_sim(CLI::App& app);
void add_debug(CLI::App& app);
void add_scene(CLI::App& app);
void add_render(CLI::App& app);
void add_demo(CLI::App& app);
void add_isa(CLI::App& app);
void add_kernels(CLI::App& app);
void add_paper(CLI::App& app);
void add_paper_gaps(CLI::App& paper_cmd); // `nesshi paper gaps`, added by add_paper
void add_paper_versus(CLI::App& paper_cmd); // `nesshi paper versus`, added by add_paper
void add_pipeline(CLI::App& app);
void add_loop(CLI::App& app);
void add_schedule(CLI::App& app);
void add_sweep(CLI::App& app);
void add_compare(CLI::App& app);
void add_completion(CLI::App& app);
} // namespace nesshi::cli
