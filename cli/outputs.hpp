// Output files are checked before the work starts: a run of minutes must not fail at its end
// because the folder of its output is missing or read-only. The writing itself is
// base::write_file / base::OutputFile (checked to the last byte); "-" is standard output.
#pragma once

#include "base/error.hpp"

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

namespace nesshi::cli {

// Throws base::Error naming `path` when it could not be created or replaced; "" and "-"
// (stdout) pass.
void check_output(const std::string& path);
inline void check_outputs(std::initializer_list<std::string> paths) {
    for (const std::string& p : paths) check_output(p);
}

// (option name, value) of the outputs of a command that may go to stdout.
using NamedOutput = std::pair<const char*, std::string>;

// True when one of `outputs` is "-" (the command's report then goes to stderr); two of them is a
// UsageError, since their bytes would mix on stdout.
bool stdout_output(const std::vector<NamedOutput>& outputs);

// A UsageError when `value` is "-": `option` has no stdout form (`why` says what to do instead).
void refuse_stdout(const char* option, const std::string& value, const char* why);

} // namespace nesshi::cli
