// Entry point of `nesshi`: builds the subcommand tree and maps errors to exit codes.
#include "commands.hpp"

#include <fmt/core.h>

#include <exception>
#include <string>

int main(int argc, char** argv) {
    CLI::App app{"nesshi: toolchain and simulator for the Nesshisen ray-tracing machine"};
    app.set_version_flag("--version", "nesshi " NESSHI_VERSION);
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
    try {
        app.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {
        // Commands signal failure with RuntimeError(message, exit code); an empty message means
        // the command already printed its own diagnostics.
        std::string what = e.what();
        if (!what.empty() && what != "Runtime error") fmt::print(stderr, "nesshi: error: {}\n", what);
        return e.get_exit_code();
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        fmt::print(stderr, "nesshi: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
