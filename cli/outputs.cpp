#include "outputs.hpp"

#include "errors.hpp"

#include <fmt/core.h>

#include <filesystem>
#include <system_error>

#include <unistd.h>

namespace nesshi::cli {

void check_output(const std::string& path) {
    if (path.empty() || path == "-") return;
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw base::Error(base::SourceLoc(path), "cannot write: it is a directory");
    if (fs::exists(path, ec)) {
        if (::access(path.c_str(), W_OK) != 0) throw base::Error(base::SourceLoc(path), "cannot write: permission denied");
        return;
    }
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    if (!fs::is_directory(dir, ec))
        throw base::Error(base::SourceLoc(path), "cannot write: no folder " + dir.string());
    if (::access(dir.c_str(), W_OK) != 0)
        throw base::Error(base::SourceLoc(path), "cannot write: the folder " + dir.string() + " is not writable");
}

bool stdout_output(const std::vector<NamedOutput>& outputs) {
    const char* first = nullptr;
    for (const auto& [name, value] : outputs) {
        if (value != "-") continue;
        if (first)
            throw UsageError(fmt::format("{} - and {} - would both write to standard output; give one of them a file",
                                         first, name));
        first = name;
    }
    return first != nullptr;
}

void refuse_stdout(const char* option, const std::string& value, const char* why) {
    if (value == "-") throw UsageError(fmt::format("{} cannot be '-' (standard output): {}", option, why));
}

} // namespace nesshi::cli
