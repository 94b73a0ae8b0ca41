// The tests' scratch folder: fresh under the system's temporary folder, removed at the end.
#pragma once

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace nesshi::test {

struct TempDir {
    std::filesystem::path path;
    // `prefix` names the test; the process id and a counter keep concurrent folders apart.
    explicit TempDir(const std::string& prefix = "nesshi-test") {
        static std::atomic<int> made{0};
        path = std::filesystem::temp_directory_path() /
               (prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(made++));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string str() const { return path.string(); }
    // Writes `text` to `name` (a path relative to the folder, parents made) and returns its path.
    std::string file(const std::string& name, const std::string& text) const {
        const std::filesystem::path p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
};

} // namespace nesshi::test
