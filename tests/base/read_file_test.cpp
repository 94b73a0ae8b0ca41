// base/read_file.hpp: regular files only, capped, and every refusal names the path.
#include "base/error.hpp"
#include "base/read_file.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

using namespace nesshi::base;
using nesshi::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string refusal(const std::string& path, std::size_t cap = kMaxInputFileBytes) {
    try {
        read_file(path, cap);
    } catch (const Error& e) {
        return e.what();
    }
    return "(read)";
}
} // namespace

TEST_CASE("read_file returns a regular file's bytes unchanged", "[unit][base]") {
    TempDir t("nesshi-read-file");
    const std::string text("a\r\nb\0c\xff", 7);
    CHECK(read_file(t.file("x.s", text)) == text);
    CHECK(read_file(t.file("empty.s", "")).empty());
}

TEST_CASE("read_file refuses directories, devices but /dev/null, and pipes without reading them", "[unit][base]") {
    TempDir t("nesshi-read-file");
    const std::string dir = t.path.string();
    CHECK(refusal(dir) == dir + ": error: is a directory");
    CHECK(refusal("/dev/zero") == "/dev/zero: error: not a regular file");
    CHECK(refusal("/dev/urandom") == "/dev/urandom: error: not a regular file");
    CHECK(read_file("/dev/null").empty()); // the usual empty input
    // A named pipe with no writer: opening it for reading would block forever.
    const std::string fifo = (t.path / "pipe").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK(refusal(fifo) == fifo + ": error: not a regular file");
}

TEST_CASE("read_file refuses a file above the cap and a file that does not exist", "[unit][base]") {
    TempDir t("nesshi-read-file");
    const std::string big = t.file("big.toml", std::string(1025, 'x'));
    CHECK(refusal(big, 1024) == big + ": error: file too large (1025 bytes; the limit is 1024)");
    CHECK(read_file(big, 1025).size() == 1025);
    CHECK(refusal("/nonexistent/x.s") == "/nonexistent/x.s: error: cannot open: No such file or directory");
    // The caps the tools use: generous for real inputs, far below what exhausts memory.
    STATIC_REQUIRE(kMaxInputFileBytes == std::size_t{256} << 20);
    STATIC_REQUIRE(kMaxMachineFileBytes == std::size_t{1} << 20);
}

TEST_CASE("read_file's error carries the path as its location", "[unit][base]") {
    try {
        read_file("/dev/zero");
        FAIL("read /dev/zero");
    } catch (const Error& e) {
        CHECK(e.loc().str() == "/dev/zero");
        CHECK(e.message() == "not a regular file");
    }
}
