// base::write_file and friends: stdio with every return value checked, fflush and fclose included.
#include "base/write_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <poll.h>
#include <sys/stat.h>

namespace nesshi::base {

namespace {

std::string write_message(const std::string& path, int error_number) {
    const std::string what = error_number ? std::strerror(error_number) : "write error";
    if (path == "-") return "writing standard output: " + what;
    return "writing '" + path + "': " + what;
}

// errno after a failed call, or EIO when the C library left none.
int last_error() { return errno ? errno : EIO; }

// The error of a stream whose failed write was not seen when it happened (stdio can accept a
// write into its buffer and fail only while flushing it; fmt and CLI11 write to stdout through
// paths that do not all check). A pipe whose reader left says so itself (POLLERR); otherwise
// errno, if nothing has changed it since, still holds the write's error.
int earlier_error(std::FILE* f, int saved_errno) {
    struct pollfd p {};
    p.fd = ::fileno(f);
    p.events = POLLOUT;
    struct stat st {};
    if (::fstat(p.fd, &st) == 0 && S_ISFIFO(st.st_mode) && ::poll(&p, 1, 0) == 1 && (p.revents & POLLERR)) return EPIPE;
    return saved_errno ? saved_errno : EIO;
}

// Flushes `f` and reports the first error it met, 0 when none.
int flush_error(std::FILE* f) {
    const int saved = errno;
    if (!std::ferror(f)) {
        errno = 0;
        if (std::fflush(f) == 0) return 0;
        return last_error();
    }
    return earlier_error(f, saved);
}

} // namespace

WriteError::WriteError(const std::string& path, int error_number)
    : Error(write_message(path, error_number)), path_(path), errno_(error_number) {}

bool WriteError::broken_pipe() const noexcept { return errno_ == EPIPE; }

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
    if (is_stdout()) {
        file_ = stdout;
        return;
    }
    errno = 0;
    file_ = std::fopen(path_.c_str(), "wb");
    if (!file_) throw WriteError(path_, last_error());
}

OutputFile::~OutputFile() {
    if (file_ && !is_stdout()) std::fclose(file_);
}

void OutputFile::write(std::string_view bytes) {
    errno = 0;
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
        throw WriteError(path_, last_error());
}

void OutputFile::close() {
    if (!file_) return;
    std::FILE* f = file_;
    file_ = nullptr;
    int err = flush_error(f);
    if (f != stdout) {
        errno = 0;
        if (std::fclose(f) != 0 && !err) err = last_error();
    }
    if (err) throw WriteError(path_, err);
}

void write_file(const std::string& path, std::string_view bytes) {
    OutputFile f(path);
    f.write(bytes);
    f.close();
}

void replace_file(const std::string& path, std::string_view bytes) {
    // Only a regular file is replaced; a device or a pipe (/dev/full, /dev/stdout) is written to:
    // renaming over it would put a plain file where the device was.
    struct stat st {};
    if (path == "-" || (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))) return write_file(path, bytes);
    const std::string tmp = path + ".tmp";
    write_file(tmp, bytes);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw WriteError(path, ec.value());
}

void flush_stdout() {
    if (const int err = flush_error(stdout)) throw WriteError("-", err);
}

} // namespace nesshi::base
