#include "kbuild/schedule_cache.hpp"

#include "schedule_cache.hpp"
#include "kbuild/kernel_build_json.hpp"

#include "base/cache_dir.hpp"
#include "base/hash.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <unistd.h>

namespace nesshi::kbuild {

namespace {

// Made on first use, so that a program may turn the cache on from a static initializer (the unit
// tests do): a namespace-scope string would be initialized again after it, empty.
struct Cache {
    std::mutex mutex;
    std::string dir, build;
};
Cache& cache() {
    static Cache c;
    return c;
}

// One folder per build: another build's schedules are never read, and its folder goes once
// unused for a while (base::prune_cache_folders).
std::string file_of(const std::string& key) {
    return cache().dir + "/" + cache().build + "/" + base::hex64(base::Fnv1a().add(key).value()) + ".json";
}

} // namespace

void enable_schedule_cache(const std::string& dir, const std::string& build) {
    {
        std::lock_guard lock(cache().mutex);
        cache().dir = dir;
        cache().build = build;
    }
    if (!dir.empty()) base::prune_cache_folders(dir, build);
}

std::string default_schedule_cache_dir() {
    if (const char* d = std::getenv("NESSHI_CACHE_DIR")) return d;
    return base::user_cache_dir("kernels");
}

namespace detail {

std::optional<StoredSchedule> load_schedule(const std::string& key) {
    std::string path, build;
    {
        std::lock_guard lock(cache().mutex);
        if (cache().dir.empty()) return std::nullopt;
        path = file_of(key);
        build = cache().build;
    }
    std::ifstream in(path);
    if (!in) return std::nullopt;
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        if (j.at("key") != key || j.at("build") != build) return std::nullopt;
        StoredSchedule s;
        s.text = j.at("text");
        s.name = j.at("name");
        s.error = j.at("error");
        s.build = build_from_json(j.at("kernel_build"));
        return s;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt; // damaged or of another layout: schedule again
    }
}

void store_schedule(const std::string& key, const StoredSchedule& s) {
    std::string path, build, dir;
    {
        std::lock_guard lock(cache().mutex);
        if (cache().dir.empty()) return;
        path = file_of(key);
        build = cache().build;
        dir = cache().dir + "/" + cache().build;
    }
    const nlohmann::json j = {{"key", key},   {"build", build},   {"text", s.text},
                              {"name", s.name}, {"error", s.error}, {"kernel_build", build_json(s.build)}};
    static std::atomic<unsigned> serial{0};
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::string tmp = path + "." + std::to_string(::getpid()) + "." + std::to_string(serial++) + ".tmp";
    {
        std::ofstream out(tmp);
        if (!out) return;
        out << j.dump();
        if (!out) {
            out.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) std::filesystem::remove(tmp, ec);
}

} // namespace detail

} // namespace nesshi::kbuild
