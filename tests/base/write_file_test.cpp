// base/write_file.hpp: every failure is a WriteError with its errno, close included; a device
// or a pipe is written to, never renamed over.
#include "base/read_file.hpp"
#include "base/write_file.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <cerrno>
#include <filesystem>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

using namespace nesshi::base;
using nesshi::test::TempDir;
namespace fs = std::filesystem;

namespace {

int write_errno(const std::string& path, const std::string& bytes) {
    try {
        write_file(path, bytes);
    } catch (const WriteError& e) {
        return e.error_number();
    }
    return 0;
}
} // namespace

TEST_CASE("write_file writes the bytes, replace_file replaces them") {
    TempDir d("nesshi-write-file");
    const std::string p = (d.path / "a.txt").string();
    write_file(p, std::string("one\0two", 7));
    CHECK(read_file(p) == std::string("one\0two", 7));
    replace_file(p, "three");
    CHECK(read_file(p) == "three");
    CHECK_FALSE(fs::exists(p + ".tmp"));
}

TEST_CASE("a full device is an error at the flush, small writes included") {
    if (::access("/dev/full", W_OK) != 0) return; // not on this system
    CHECK(write_errno("/dev/full", "x") == ENOSPC);
    CHECK(write_errno("/dev/full", std::string(1 << 20, 'x')) == ENOSPC);
    try {
        write_file("/dev/full", "x");
        FAIL("no error");
    } catch (const WriteError& e) {
        CHECK(std::string(e.what()) == "writing '/dev/full': No space left on device");
        CHECK_FALSE(e.broken_pipe());
    }
    OutputFile f("/dev/full");
    f.write("abc");
    CHECK_THROWS_AS(f.close(), WriteError);
    f.close(); // once closed, closing again does nothing
}

TEST_CASE("a missing folder is an error naming the path") {
    CHECK(write_errno("/nonexistent-folder/x", "x") == ENOENT);
}

TEST_CASE("replace_file writes into a pipe instead of renaming a file over it") {
    TempDir d("nesshi-write-file");
    const std::string p = (d.path / "pipe").string();
    REQUIRE(::mkfifo(p.c_str(), 0600) == 0);
    // A reader must be there for the open for writing to succeed.
    const int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK);
    REQUIRE(fd >= 0);
    replace_file(p, "hello");
    char buf[16] = {};
    CHECK(::read(fd, buf, sizeof buf) == 5);
    ::close(fd);
    struct stat st {};
    REQUIRE(::stat(p.c_str(), &st) == 0);
    CHECK(S_ISFIFO(st.st_mode));
}
