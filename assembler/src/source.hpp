// Source files, locations and clang-style diagnostics (`file:line:col: error: ...`, line, caret).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::assembler {

struct Loc {
    int file = -1; // index into SourceSet::files; -1 = no location
    int line = 0;  // 1-based; 0: the file as a whole (no source line shown)
    int col = 0;   // 1-based
};

struct SourceFile {
    std::string name;  // as shown in diagnostics
    std::string dir;   // directory for relative .include
    std::vector<std::string> lines;
};

struct SourceSet {
    std::vector<SourceFile> files;
    int add(std::string name, std::string_view text);
    std::string_view line(const Loc& loc) const;
};

enum class Severity : uint8_t { Error, Warning, Note };

struct Diagnostic {
    Severity severity = Severity::Error;
    Loc loc;
    std::string message;
    std::vector<Diagnostic> notes;
};

// Source lines longer than this are cut around the caret in diagnostics ("..." marks the cuts).
inline constexpr size_t kMaxShownLine = 160;

// Collects diagnostics; render() prints them in source order. Like clang's -ferror-limit, it
// keeps the first `error_limit` errors (0: all) and then stops: later errors are dropped,
// stopped() tells the passes to end, and render() closes with "too many errors emitted".
class Diagnostics {
  public:
    explicit Diagnostics(const SourceSet& sources, int error_limit = 0)
        : sources_(sources), error_limit_(error_limit) {}
    Diagnostic& error(Loc loc, std::string message);
    Diagnostic& warning(Loc loc, std::string message);
    static void note(Diagnostic& d, Loc loc, std::string message);
    int errors() const { return errors_; }
    int warnings() const { return warnings_; }
    bool stopped() const { return stopped_; }
    std::string render() const;
    // Errors and warnings in render()'s order, without their notes.
    std::vector<const Diagnostic*> in_order() const;
    const SourceSet& sources() const { return sources_; }

  private:
    std::string render_one(const Diagnostic& d) const;
    const SourceSet& sources_;
    std::vector<Diagnostic> list_;
    Diagnostic dropped_; // what error() returns once stopped: notes added to it go nowhere
    int error_limit_ = 0;
    bool stopped_ = false;
    int errors_ = 0;
    int warnings_ = 0;
};

} // namespace nesshi::assembler
