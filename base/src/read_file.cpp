// base::read_file: stat, open without blocking, check again on the open file, read up to the cap.
#include "base/read_file.hpp"

#include "base/error.hpp"

#include <cerrno>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace nesshi::base {

namespace {

[[noreturn]] void fail(const std::string& path, std::string message) {
    throw Error(SourceLoc(path), std::move(message));
}

// "cannot open: No such file or directory": what the system said, so that the user knows why.
[[noreturn]] void fail_open(const std::string& path) { fail(path, std::string("cannot open: ") + std::strerror(errno)); }

// The null device: the usual way to give a command an empty input (`--fifo-in /dev/null`).
bool is_null_device(const struct stat& st) {
    struct stat null {};
    return S_ISCHR(st.st_mode) && ::stat("/dev/null", &null) == 0 && S_ISCHR(null.st_mode) && st.st_rdev == null.st_rdev;
}

// Refuses what is not a regular file of at most `max_bytes`.
void check_kind(const std::string& path, const struct stat& st, std::size_t max_bytes) {
    if (S_ISDIR(st.st_mode)) fail(path, "is a directory");
    if (!S_ISREG(st.st_mode)) fail(path, "not a regular file");
    if (st.st_size > 0 && static_cast<unsigned long long>(st.st_size) > max_bytes)
        fail(path, "file too large (" + std::to_string(st.st_size) + " bytes; the limit is " +
                       std::to_string(max_bytes) + ")");
}

struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

} // namespace

std::string read_file(const std::string& path, std::size_t max_bytes) {
    // stat first, so a device or a pipe is never even opened; fstat again on what was opened,
    // in case the path changed in between.
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) fail_open(path);
    if (is_null_device(st)) return {};
    check_kind(path, st, max_bytes);
    Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
    if (f.fd < 0) fail_open(path);
    if (::fstat(f.fd, &st) != 0) fail_open(path);
    check_kind(path, st, max_bytes);

    // Read to the end rather than trusting st_size (files that grow, /proc files of size 0),
    // but never past the cap.
    std::string out;
    out.reserve(static_cast<std::size_t>(st.st_size));
    char buf[1 << 16];
    while (true) {
        const ssize_t n = ::read(f.fd, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR) continue;
            fail(path, std::string("cannot read: ") + std::strerror(errno));
        }
        if (n == 0) break;
        if (out.size() + static_cast<std::size_t>(n) > max_bytes)
            fail(path, "file too large (at least " + std::to_string(out.size() + static_cast<std::size_t>(n)) +
                           " bytes; the limit is " + std::to_string(max_bytes) + ")");
        out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
}

} // namespace nesshi::base
