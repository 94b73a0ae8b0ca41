// The single-step debugger behind `nesshi debug`: commands from one table, output to a FILE.
//
// Every command is one row of Debugger::commands() (name, aliases, argument syntax, help,
// handler), so `help` cannot drift. Wherever a value or address is expected, a number
// (decimal, 0x hex), a label (code labels give bundle addresses, data labels byte addresses),
// LABEL+N / LABEL-N, or a register name (its current value) is accepted.
#pragma once

#include "iss/processor.hpp"

#include <fmt/core.h>

#include <atomic>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::iss {

class Debugger;

struct DebugCommand {
    std::string_view name;
    std::vector<std::string_view> aliases;
    std::string_view args;
    std::string_view help;
    void (Debugger::*run)(const std::vector<std::string>& args);
};

class Debugger {
  public:
    Debugger(Processor& p, std::FILE* out);

    // Runs one command line. An empty or blank line repeats the last `step`. Returns false after
    // `quit`.
    bool execute(std::string_view line);
    static const std::vector<DebugCommand>& commands();

    // A value: number, label[+-N], or register name (its value). nullopt (and a message) when bad.
    std::optional<uint32_t> value(std::string_view tok);
    // A code location: a number, a code label[+-N], or a register holding a bundle address.
    std::optional<uint32_t> location(std::string_view tok);

    uint64_t max_cycles = 100'000'000; // `step`, `continue` and `until` stop after this many cycles

    // Set (by the SIGINT handler of debug_interactive, or by any thread) to stop a running
    // `continue`, `until`, `step` or `run` before its next bundle; the state is kept, and the
    // flag is cleared when the run stops on it. Lock-free, so a signal handler may set it.
    std::atomic<bool> interrupt{false};

    // Called by `run` and `restart` after the processor is back to its loaded state: the host
    // re-creates what the program reads (e.g. refills its input FIFOs). Breakpoints and watches stay.
    std::function<void()> on_restart;

    // TAB completion: the candidates for the last word of `line` (the text before the cursor):
    // command names for the first word, `info` topics after `info`, else register names and
    // labels. Sorted, without duplicates.
    std::vector<std::string> complete(std::string_view line) const;

  private:
    void cmd_step(const std::vector<std::string>& a);
    void cmd_continue(const std::vector<std::string>& a);
    void cmd_run(const std::vector<std::string>& a);
    void cmd_restart(const std::vector<std::string>& a);
    void cmd_until(const std::vector<std::string>& a);
    void cmd_break(const std::vector<std::string>& a);
    void cmd_delete(const std::vector<std::string>& a);
    void cmd_watch(const std::vector<std::string>& a);
    void cmd_info(const std::vector<std::string>& a);
    void cmd_examine(const std::vector<std::string>& a);
    void cmd_disas(const std::vector<std::string>& a);
    void cmd_print(const std::vector<std::string>& a);
    void cmd_stats(const std::vector<std::string>& a);
    void cmd_help(const std::vector<std::string>& a);
    void cmd_quit(const std::vector<std::string>& a);

    void info_regs(char which);
    void info_inflight();
    void info_ports();
    void info_breaks();

    // Runs bundle by bundle until `stop` says so, a breakpoint, a watch change, or the run ends.
    void run_until(const std::function<bool()>& stop, bool stop_at_breaks);
    void where();
    void restart(); // the processor and its inputs back to the loaded state
    bool finished();
    std::string loc_text(uint32_t pc) const;

    template <typename... T> void say(fmt::format_string<T...> f, T&&... args) {
        fmt::print(out_, f, std::forward<T>(args)...);
    }

    struct Watch {
        bool is_reg = true;
        uint32_t where = 0; // flat register or byte address
        uint32_t last = 0;
    };
    bool read_watch(const Watch& w, uint32_t& v) const;

    Processor& p_;
    std::FILE* out_;
    std::vector<std::pair<int, uint32_t>> breaks_; // (id, pc)
    std::vector<std::pair<int, Watch>> watches_;
    int next_id_ = 1;
    std::vector<std::string> last_step_; // the words of the last step command, repeated by Enter
    bool quit_ = false;
};

// Reads commands with line editing, TAB completion (Debugger::complete) and history until
// `quit` or end of input (Ctrl-D). Ctrl-C during a run stops it (Debugger::interrupt); at the
// prompt it clears the line. The history persists in debug_history_path() when that is not empty.
void debug_interactive(Debugger& d);
// The history file: $XDG_STATE_HOME/nesshi_history when XDG_STATE_HOME is set (and not empty),
// else $HOME/.nesshi_history, else "" (no history is kept). Arguments are the variables' values
// (nullptr when unset).
std::string debug_history_path(const char* xdg_state_home, const char* home);
// Runs the commands of a script file, echoing each after a "(nesshi) " prompt (for goldens).
// Throws base::Error (a std::runtime_error) when base::read_file refuses the file.
void debug_script(Debugger& d, const std::string& path, std::FILE* out);

} // namespace nesshi::iss
