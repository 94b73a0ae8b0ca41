// Output files are checked before the work starts: a run of minutes must not fail at its end
// because the folder of its output is missing or read-only.
#pragma once

#include "base/error.hpp"

#include <initializer_list>
#include <string>

namespace nesshi::cli {

// Throws base::Error naming `path` when it could not be created or replaced; "" and "-"
// (stdout) pass.
void check_output(const std::string& path);
inline void check_outputs(std::initializer_list<std::string> paths) {
    for (const std::string& p : paths) check_output(p);
}

} // namespace nesshi::cli
