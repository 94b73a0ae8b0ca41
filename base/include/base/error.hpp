// The one error type of every library: a message and, when known, where in the input it arose.
//
// Libraries throw subclasses that name the kind of input (isa::MachineError, isa::ObjectError,
// iss::LoadError, rt::SceneError, paper::PaperError) so callers can catch one kind; all of them
// are base::Error, and format_error is the only place that spells "file:line:col: error:".
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace nesshi::base {

// A place in an input: a file (or a preset name, or "<input>"), with a line and a column when
// known (0 = unknown). Prints as "file", "file:line" or "file:line:col"; no file prints nothing.
struct SourceLoc {
    std::shared_ptr<const std::string> file; // shared by every record that points into one file
    int line = 0;
    int col = 0;

    SourceLoc() = default;
    explicit SourceLoc(std::string_view f, int l = 0, int c = 0)
        : file(std::make_shared<const std::string>(f)), line(l), col(c) {}
    SourceLoc(std::shared_ptr<const std::string> f, int l, int c) : file(std::move(f)), line(l), col(c) {}

    bool known() const { return file != nullptr; }
    std::string str() const;
};

// "loc: error: message", or the message alone when the location is unknown.
std::string format_error(const SourceLoc& loc, std::string_view message);

class Error : public std::runtime_error {
  public:
    Error(SourceLoc loc, std::string message)
        : std::runtime_error(format_error(loc, message)), loc_(std::move(loc)), message_(std::move(message)) {}
    explicit Error(std::string message) : Error(SourceLoc{}, std::move(message)) {}

    const SourceLoc& loc() const noexcept { return loc_; }
    const std::string& message() const noexcept { return message_; } // without the location

  private:
    SourceLoc loc_;
    std::string message_;
};

inline std::string SourceLoc::str() const {
    if (!file) return {};
    std::string s = *file;
    if (line > 0) {
        s += ':' + std::to_string(line);
        if (col > 0) s += ':' + std::to_string(col);
    }
    return s;
}

inline std::string format_error(const SourceLoc& loc, std::string_view message) {
    if (!loc.known()) return std::string(message);
    return loc.str() + ": error: " + std::string(message);
}

} // namespace nesshi::base
