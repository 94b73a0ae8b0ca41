#include "errors.hpp"
#include "status.hpp"

#include "base/error.hpp"
#include "base/suggest.hpp"
#include "base/write_file.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <string>
#include <system_error>

namespace nesshi::cli {

namespace {

// The last of the chain of subcommands that parsed (`app` itself when none did).
const CLI::App& deepest(const CLI::App& app) {
    const CLI::App* a = &app;
    while (!a->get_subcommands().empty()) a = a->get_subcommands().front();
    return *a;
}

// "nesshi scene info": the chain of subcommands that parsed.
std::string command_name(const CLI::App& app) {
    std::string name = "nesshi";
    for (const CLI::App* a = &app; !a->get_subcommands().empty();) {
        a = a->get_subcommands().front();
        name += " " + a->get_name();
    }
    return name;
}

// The subcommands `app` offers, and its long options ("--model").
std::vector<std::string> subcommand_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(s->get_name());
    return names;
}
std::vector<std::string> long_options(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app.get_options())
        for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    return names;
}

// "did you mean" for the first unexpected word that is near an option (or a subcommand) of the
// command that parsed.
std::string suggest_for(const CLI::App& app, const std::vector<std::string>& words) {
    for (const std::string& w : words) {
        const std::string name = w.substr(0, w.find('='));
        const std::string hint = base::did_you_mean(name, name.starts_with("--") ? long_options(app) : subcommand_names(app));
        if (!hint.empty()) return hint;
    }
    return "";
}

void print_usage_error(const std::string& who, const std::string& msg) {
    status("{}: error: {}\nRun '{} --help' for more information.\n", who, msg, who);
}

} // namespace

const char* exit_status_help() {
    return "Exit status: 0 success, 1 bad input, failed check or failed write, 2 usage error, 3 simulated fault.\n"
           "A reader that stops early (| head) ends a command quietly with 0, however much it had written.";
}

int report_error(const CLI::App& app, std::exception_ptr error) {
    const std::string who = command_name(app);
    try {
        std::rethrow_exception(error);
    } catch (const CLI::Success& e) { // --help, --help-all, --version
        return app.exit(e);
    } catch (const CLI::RequiredError& e) {
        // CLI11 reads an unknown first word as a missing subcommand (`nesshi frob`, `nesshi scene frob`).
        const std::vector<std::string> rest = deepest(app).remaining();
        if (!rest.empty() && std::string(e.what()).find("subcommand is required") != std::string::npos)
            print_usage_error(who, fmt::format("unknown command '{}'{} (see the list in '{} --help')", rest.front(),
                                               base::did_you_mean(rest.front(), subcommand_names(deepest(app))), who));
        else
            print_usage_error(who, e.what());
        return kExitUsage;
    } catch (const CLI::ValidationError& e) { // "--pes: must be ..." (ranges.hpp) reads "--pes must be ..."
        std::string msg = e.what();
        if (const auto at = msg.find(": must be "); at != std::string::npos) msg.erase(at, 1);
        print_usage_error(who, msg);
        return kExitUsage;
    } catch (const CLI::ExtrasError& e) {
        print_usage_error(who, e.what() + suggest_for(deepest(app), deepest(app).remaining()));
        return kExitUsage;
    } catch (const CLI::ParseError& e) {
        print_usage_error(who, e.what());
        return kExitUsage;
    } catch (const UsageError& e) {
        print_usage_error(who, e.what());
        return kExitUsage;
    } catch (const Reported& e) {
        return e.status();
    } catch (const base::WriteError& e) {
        if (e.broken_pipe()) return kExitOk; // the reader went away (`| head -1`): end quietly (exit_status_help)
        status("{}: error: {}\n", who, e.message());
        return kExitInput;
    } catch (const base::Error& e) {
        if (e.loc().known()) status("{}\n", e.what());
        else status("{}: error: {}\n", who, e.message());
        return kExitInput;
    } catch (const std::system_error& e) {
        // fmt::print throws this when a write fails. Files go through base::write_file and
        // OutputFile (WriteError, which names them), so this one was a print to standard output.
        if (e.code() == std::errc::broken_pipe) return kExitOk;
        status("{}: error: {}\n", who, base::WriteError("-", e.code().value()).message());
        return kExitInput;
    } catch (const std::exception& e) {
        status("{}: error: {}\n", who, e.what());
        return kExitInput;
    }
    return kExitInput;
}

} // namespace nesshi::cli
