// Entry point of `nesshi`: builds the subcommand tree; errors.cpp turns failures into exit codes.
#include "commands.hpp"
#include "errors.hpp"

#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"nesshi: toolchain and simulator for the Nesshisen ray-tracing machine"};
    app.set_version_flag("--version", "nesshi " NESSHI_VERSION);
    app.footer(nesshi::cli::exit_status_help());
    app.require_subcommand(1);
    nesshi::cli::add_asm(app);
    nesshi::cli::add_dis(app);
    nesshi::cli::add_sim(app);
    nesshi::cli::add_debug(app);
    nesshi::cli::add_scene(app);
    nesshi::cli::add_render(app);
    nesshi::cli::add_demo(app);
    nesshi::cli::add_isa(app);
    nesshi::cli::add_kernels(app);
    nesshi::cli::add_paper(app);
    nesshi::cli::add_pipeline(app);
    nesshi::cli::add_loop(app);
    nesshi::cli::add_schedule(app);
    nesshi::cli::one_value_per_option(app);
    try {
        app.parse(argc, argv);
    } catch (...) {
        return nesshi::cli::report_error(app, std::current_exception());
    }
    return nesshi::cli::kExitOk;
}
