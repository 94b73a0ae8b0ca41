// Entry point of `nesshi`: builds the subcommand tree; errors.cpp turns failures into exit codes.
#include "commands.hpp"
#include "errors.hpp"

#include "base/write_file.hpp"
#include "machine/provenance.hpp"

#include <fmt/format.h>

#include <csignal>
#include <exception>
#include <string_view>
#include <vector>

namespace {

// GNU habit: an option takes one value per occurrence (`-I a -I b file.s`), so it never
// swallows the positional argument after it. Applies to every option of every subcommand, not to
// positionals: CLI11 gives a positional more values than its minimum only through extra args
// (`nesshi compare A B C`).
void one_value_per_option(CLI::App& app) {
    for (CLI::Option* o : app.get_options())
        if (!o->get_positional() && o->get_items_expected_max() > 1) o->allow_extra_args(false);
    for (CLI::App* sub : app.get_subcommands({})) one_value_per_option(*sub);
}

} // namespace

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
    nesshi::cli::add_sweep(app);
    nesshi::cli::add_compare(app);
    nesshi::cli::add_completion(app);
    one_value_per_option(app);
    // Kernels scheduled for a machine file are kept between runs (NESSHI_CACHE_DIR= turns it off).
    nesshi::machine::enable_default_schedule_cache();
    // A closed pipe (`nesshi isa | head -1`) is an EPIPE write error, which ends the command
    // quietly (errors.cpp), instead of a SIGPIPE that kills it half-way through writing a file.
    std::signal(SIGPIPE, SIG_IGN);
    // `nesshi help [COMMAND...]` is `nesshi [COMMAND...] --help`, as git and cargo have it.
    std::vector<char*> args(argv, argv + argc);
    static char help_flag[] = "--help";
    if (args.size() > 1 && std::string_view(args[1]) == "help") {
        args.erase(args.begin() + 1);
        args.push_back(help_flag);
    }
    int status = nesshi::cli::kExitOk;
    try {
        // Options belong to commands: `nesshi -q render` read -q as the top level's and then said
        // "scene is required".
        if (args.size() > 1 && args[1][0] == '-') {
            const std::string_view first = args[1];
            if (first != "-h" && first != "--help" && first != "--help-all" && first != "--version")
                throw nesshi::cli::UsageError(fmt::format(
                    "'{}' is an option of a command: write it after the command (nesshi COMMAND {} ...)", first, first));
        }
        app.parse(static_cast<int>(args.size()), args.data());
    } catch (...) {
        status = nesshi::cli::report_error(app, std::current_exception());
    }
    try {
        nesshi::base::flush_stdout(); // what was printed really arrived (`nesshi isa > /dev/full`, --help too)
    } catch (...) {
        // Said once: a command that failed (a full disk while printing, say) has reported it already.
        if (status == nesshi::cli::kExitOk) status = nesshi::cli::report_error(app, std::current_exception());
    }
    return status;
}
