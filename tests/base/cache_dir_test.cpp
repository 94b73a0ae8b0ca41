// base/cache_dir.hpp: trimming a cache folder to a size removes the least recently written files
// of one kind first, never the one named to keep nor one in use.
#include "base/cache_dir.hpp"
#include "base/write_file.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <string>

using namespace nesshi::base;
using nesshi::test::TempDir;
namespace fs = std::filesystem;

namespace {

// A file of `bytes` bytes written `age` hours ago.
void put(const std::string& dir, const std::string& name, std::size_t bytes, int age) {
    write_file(dir + "/" + name, std::string(bytes, 'x'));
    fs::last_write_time(dir + "/" + name, fs::file_time_type::clock::now() - std::chrono::hours(age));
}

} // namespace

TEST_CASE("trim_cache_files removes the least recently written files of the kind first", "[cache_dir]") {
    TempDir t;
    const std::string d = t.str();
    put(d, "old.so", 100, 3);
    put(d, "mid.so", 100, 2);
    put(d, "new.so", 100, 1);
    put(d, "kept.so", 100, 4); // the oldest, but the one named to keep
    put(d, "notes.log", 1000, 9); // another kind: neither counted nor removed
    trim_cache_files(d, ".so", 250, "kept.so");
    CHECK_FALSE(fs::exists(d + "/old.so"));
    CHECK_FALSE(fs::exists(d + "/mid.so"));
    CHECK(fs::exists(d + "/new.so"));
    CHECK(fs::exists(d + "/kept.so"));
    CHECK(fs::exists(d + "/notes.log"));
}

TEST_CASE("trim_cache_files leaves a folder within its limit alone, and a touched file is recent", "[cache_dir]") {
    TempDir t;
    const std::string d = t.str();
    put(d, "a.so", 100, 2);
    put(d, "b.so", 100, 1);
    trim_cache_files(d, ".so", 200, "");
    CHECK(fs::exists(d + "/a.so"));
    CHECK(fs::exists(d + "/b.so"));
    touch_cache_file(d + "/a.so"); // a.so loaded: b.so is now the least recently used
    trim_cache_files(d, ".so", 100, "");
    CHECK(fs::exists(d + "/a.so"));
    CHECK_FALSE(fs::exists(d + "/b.so"));
    trim_cache_files(d + "/missing", ".so", 0, ""); // no folder: nothing to do, no throw
}

TEST_CASE("trim_cache_files leaves a file in use, and goes on to the next", "[cache_dir]") {
    TempDir t;
    const std::string d = t.str();
    put(d, "old.so", 100, 3); // the oldest, but being loaded elsewhere
    put(d, "mid.so", 100, 2);
    put(d, "new.so", 100, 1);
    trim_cache_files(d, ".so", 100, "", [](const std::string& name) { return name == "old.so"; });
    CHECK(fs::exists(d + "/old.so"));
    CHECK_FALSE(fs::exists(d + "/mid.so"));
    CHECK_FALSE(fs::exists(d + "/new.so")); // still over the limit without the busy one
}
