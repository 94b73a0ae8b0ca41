#include "base/cache_dir.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <vector>

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

void trim_cache_files(const std::string& dir, std::string_view extension, std::uint64_t max_bytes, const std::string& keep,
                      const std::function<bool(const std::string&)>& busy) {
    namespace fs = std::filesystem;
    struct File {
        fs::path path;
        fs::file_time_type when;
        std::uint64_t bytes;
    };
    std::vector<File> files;
    std::uint64_t total = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (!name.ends_with(extension) || !it->is_regular_file(ec)) continue;
        const std::uint64_t bytes = it->file_size(ec);
        const fs::file_time_type when = it->last_write_time(ec);
        if (ec) continue; // gone meanwhile
        total += bytes;
        if (name != keep) files.push_back({it->path(), when, bytes});
    }
    std::sort(files.begin(), files.end(), [](const File& a, const File& b) { return a.when < b.when; });
    for (const File& f : files) {
        if (total <= max_bytes) break;
        if (busy && busy(f.path.filename().string())) continue;
        fs::remove(f.path, ec);
        if (!fs::exists(f.path, ec)) total -= f.bytes; // removed, by us or by another process trimming too
    }
}

void touch_cache_file(const std::string& path) {
    std::error_code ec;
    std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now(), ec);
}

} // namespace nesshi::base
