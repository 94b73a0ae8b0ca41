#include "base/cache_dir.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>

namespace nesshi::base {

std::string user_cache_dir(std::string_view kind) {
    // A relative XDG_CACHE_HOME is ignored, as the XDG base directory specification asks.
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x == '/') return std::string(x) + "/nesshi/" + std::string(kind);
    if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/nesshi/" + std::string(kind);
    return "";
}

void prune_cache_folders(const std::string& dir, const std::string& keep) {
    namespace fs = std::filesystem;
    constexpr auto kPruneAfter = std::chrono::hours(24 * 30);
    std::error_code ec;
    const auto now = fs::file_time_type::clock::now();
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (!it->is_directory(ec) || it->path().filename() == keep) continue;
        const auto when = fs::last_write_time(it->path(), ec);
        if (!ec && now - when > kPruneAfter) fs::remove_all(it->path(), ec);
    }
}

} // namespace nesshi::base
