// The debugger's input loops: interactive (libedit line editing, completion and history) and scripted.
#include "iss/debugger.hpp"

#include "base/read_file.hpp"

#include <editline/readline.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace nesshi::iss {

namespace {

// The session's interrupt flag, for the SIGINT handler (one interactive session at a time).
std::atomic<bool>* g_interrupt = nullptr;
std::atomic<bool> g_sigint{false}; // a SIGINT arrived (at the prompt: clear the line)

extern "C" void on_sigint(int) {
    g_sigint.store(true);
    if (g_interrupt) g_interrupt->store(true);
}

// TAB completion through Debugger::complete.
const Debugger* g_debugger = nullptr;
std::vector<std::string> g_matches;

char* completion_entry(const char* /*text*/, int state) {
    if (state < 0 || size_t(state) >= g_matches.size()) return nullptr;
    return strdup(g_matches[size_t(state)].c_str());
}

char** attempt_completion(const char* text, int start, int end) {
    rl_attempted_completion_over = 1; // never fall back to file names
    if (!g_debugger) return nullptr;
    std::string line(rl_line_buffer ? rl_line_buffer : "", size_t(std::max(0, end)));
    (void)start;
    (void)text;
    g_matches = g_debugger->complete(line);
    if (g_matches.empty()) return nullptr;
    return rl_completion_matches(text, completion_entry);
}

} // namespace

std::string debug_history_path(const char* xdg_state_home, const char* home) {
    if (xdg_state_home && *xdg_state_home) return std::string(xdg_state_home) + "/nesshi_history";
    if (home && *home) return std::string(home) + "/.nesshi_history";
    return {};
}

void debug_interactive(Debugger& d) {
    // SIGINT sets the flags; no SA_RESTART, so a read at the prompt returns and the line is dropped.
    g_interrupt = &d.interrupt;
    struct sigaction sa {}, old_sa{};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    sigaction(SIGINT, &sa, &old_sa);
    rl_catch_signals = 0;

    g_debugger = &d;
    rl_attempted_completion_function = attempt_completion;
    rl_completer_word_break_characters = const_cast<char*>(" \t");

    const std::string hist = debug_history_path(std::getenv("XDG_STATE_HOME"), std::getenv("HOME"));
    using_history();
    stifle_history(1000);
    if (!hist.empty()) read_history(hist.c_str()); // a missing file is a fresh history

    while (true) {
        g_sigint.store(false);
        char* line = readline("(nesshi) ");
        if (!line) {
            if (g_sigint.exchange(false)) { // Ctrl-C at the prompt: a fresh line
                d.interrupt.store(false);
                std::fputs("\n", stdout);
                std::fflush(stdout);
                continue;
            }
            std::fputs("\n", stdout); // Ctrl-D: end of input
            break;
        }
        std::string text(line);
        std::free(line);
        if (g_sigint.exchange(false)) { // Ctrl-C while typing, the line returned anyway: drop it
            d.interrupt.store(false);
            continue;
        }
        if (text.find_first_not_of(" \t") != std::string::npos) add_history(text.c_str());
        d.interrupt.store(false); // a Ctrl-C before the command started does not stop it
        if (!d.execute(text)) break;
    }
    if (!hist.empty()) write_history(hist.c_str()); // best effort: an unwritable file loses the history only

    rl_attempted_completion_function = nullptr;
    g_debugger = nullptr;
    sigaction(SIGINT, &old_sa, nullptr);
    g_interrupt = nullptr;
}

void debug_script(Debugger& d, const std::string& path, std::FILE* out) {
    std::istringstream in(base::read_file(path));
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        fmt::print(out, "(nesshi) {}\n", line);
        if (!d.execute(line)) return;
    }
}

} // namespace nesshi::iss
