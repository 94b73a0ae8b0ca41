#include "outputs.hpp"

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

} // namespace nesshi::cli
