// The one place where an error becomes a message on stderr and an exit status.
//
// Commands throw and never print an error themselves. An error that knows its input (a
// base::Error with a location) prints as "file:line:col: error: message"; any other as
// "nesshi CMD: error: message", CMD being the subcommand that ran ("scene info"). A failed write
// is "nesshi CMD: error: writing 'PATH': No space left on device" (exit 1); a broken pipe (the
// reader of stdout went away) ends the command quietly, exit 1.
#pragma once

#include "base/error.hpp"

#include <CLI/CLI.hpp>

#include <exception>
#include <stdexcept>

namespace nesshi::cli {

// The exit statuses of every command (also in `nesshi --help` and the README).
enum Exit : int {
    kExitOk = 0,
    kExitInput = 1, // bad input, failed check or verification, unwritable output or a failed write
    kExitUsage = 2, // bad command line: unknown command or option, bad option value
    kExitFault = 3, // the simulated program faulted (or deadlocked, or hit its cycle limit)
};

// A bad command line that the option parser cannot see (a bad value inside an option's text).
class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The command has printed its own diagnostics (the assembler's, a fault report): exit quietly.
class Reported : public std::exception {
  public:
    explicit Reported(int status) : status_(status) {}
    int status() const { return status_; }
    const char* what() const noexcept override { return "diagnostics already printed"; }

  private:
    int status_;
};

// Prints what `error` means (help and version included) and returns the exit status.
int report_error(const CLI::App& app, std::exception_ptr error);

// The footer of `nesshi --help`: the exit statuses above, in words.
const char* exit_status_help();

} // namespace nesshi::cli
