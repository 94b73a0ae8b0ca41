// Status, progress and error text for stderr: never throws. A closed stderr (`2>&1 | head -2`)
// drops the text and the work goes on (a fmt::print that throws on EPIPE in a worker thread
// aborted `nesshi sweep` after two cells, with no results written).
#pragma once

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <utility>

namespace nesshi::cli {

template <typename... Args>
void status(fmt::format_string<Args...> format, Args&&... args) {
    const std::string text = fmt::format(format, std::forward<Args>(args)...);
    (void)std::fwrite(text.data(), 1, text.size(), stderr);
}

} // namespace nesshi::cli
