// The one way the tools write an output: checked to the last byte, close included.
//
//   base::write_file(path, text);          // whole contents; "-" is standard output
//   base::replace_file(path, text);        // via PATH.tmp and a rename: a failed write leaves the old file whole
//   base::OutputFile f(path);              // a stream (traces, PNG rows): write to f.get(), then
//   f.close();                             // flush and close, checked
//   base::flush_stdout();                  // at exit (or before stderr): what was printed on stdout arrived
//
// Every failure (cannot open, a short write, a failing flush or fclose: a full disk, /dev/full, a
// closed pipe) throws WriteError, "writing 'PATH': No space left on device", with the errno, so a
// caller can end quietly on a broken pipe (broken_pipe()).
#pragma once

#include "base/error.hpp"

#include <cstdio>
#include <string>
#include <string_view>

namespace nesshi::base {

class WriteError : public Error {
  public:
    // `path` "-" is standard output. `error_number` is an errno value.
    WriteError(const std::string& path, int error_number);
    const std::string& path() const noexcept { return path_; }
    int error_number() const noexcept { return errno_; }
    bool broken_pipe() const noexcept; // EPIPE: the reader went away (`nesshi ... | head -1`)

  private:
    std::string path_;
    int errno_;
};

// An output opened for writing; "-" is standard output (flushed by close(), never closed).
class OutputFile {
  public:
    explicit OutputFile(std::string path); // throws WriteError when it cannot be opened
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    ~OutputFile(); // closes unchecked if close() was not called (an error is already on its way)

    std::FILE* get() const noexcept { return file_; }
    const std::string& path() const noexcept { return path_; }
    bool is_stdout() const noexcept { return path_ == "-"; }
    void write(std::string_view bytes); // throws WriteError on a short write
    void close();                       // flush, check the stream, fclose; throws WriteError

  private:
    std::string path_;
    std::FILE* file_ = nullptr;
};

void write_file(const std::string& path, std::string_view bytes);
void replace_file(const std::string& path, std::string_view bytes);

// Flushes standard output and checks that nothing written to it was lost; throws WriteError("-").
void flush_stdout();

} // namespace nesshi::base
