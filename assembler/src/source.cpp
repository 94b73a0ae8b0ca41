// Source bookkeeping and diagnostic rendering (see source.hpp).
#include "source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

namespace nesshi::assembler {

int SourceSet::add(std::string name, std::string_view text) {
    SourceFile f;
    auto slash = name.find_last_of('/');
    f.dir = slash == std::string::npos ? std::string() : name.substr(0, slash + 1);
    f.name = std::move(name);
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t nl = text.find('\n', pos);
        if (nl == std::string_view::npos) {
            if (pos < text.size()) f.lines.emplace_back(text.substr(pos));
            break;
        }
        std::string_view l = text.substr(pos, nl - pos);
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        f.lines.emplace_back(l);
        pos = nl + 1;
    }
    files.push_back(std::move(f));
    return int(files.size()) - 1;
}

std::string_view SourceSet::line(const Loc& loc) const {
    if (loc.file < 0 || loc.file >= int(files.size())) return {};
    const auto& lines = files[size_t(loc.file)].lines;
    if (loc.line < 1 || loc.line > int(lines.size())) return {};
    return lines[size_t(loc.line - 1)];
}

Diagnostic& Diagnostics::error(Loc loc, std::string message) {
    ++errors_;
    list_.push_back({Severity::Error, loc, std::move(message), {}});
    return list_.back();
}

Diagnostic& Diagnostics::warning(Loc loc, std::string message) {
    ++warnings_;
    list_.push_back({Severity::Warning, loc, std::move(message), {}});
    return list_.back();
}

void Diagnostics::note(Diagnostic& d, Loc loc, std::string message) {
    d.notes.push_back({Severity::Note, loc, std::move(message), {}});
}

std::string Diagnostics::render_one(const Diagnostic& d) const {
    static constexpr std::string_view kWords[] = {"error", "warning", "note"};
    std::string_view word = kWords[int(d.severity)];
    if (d.loc.file < 0) return fmt::format("error: {}\n", d.message);
    std::string out = fmt::format("{}:{}:{}: {}: {}\n", sources_.files[size_t(d.loc.file)].name,
                                  d.loc.line, d.loc.col, word, d.message);
    std::string_view text = sources_.line(d.loc);
    out += text;
    out += '\n';
    // Keep tabs so the caret lines up with the source line in any terminal.
    for (int i = 0; i + 1 < d.loc.col && size_t(i) < text.size(); ++i)
        out += text[size_t(i)] == '\t' ? '\t' : ' ';
    out += "^\n";
    return out;
}

std::string Diagnostics::render() const {
    // In source order (the passes find problems in different orders); ties keep discovery order.
    std::vector<const Diagnostic*> sorted;
    for (const auto& d : list_) sorted.push_back(&d);
    std::stable_sort(sorted.begin(), sorted.end(), [](const Diagnostic* a, const Diagnostic* b) {
        return std::tie(a->loc.file, a->loc.line, a->loc.col) < std::tie(b->loc.file, b->loc.line, b->loc.col);
    });
    std::string out;
    for (const Diagnostic* p : sorted) {
        const Diagnostic& d = *p;
        out += render_one(d);
        for (const auto& n : d.notes) out += render_one(n);
    }
    return out;
}

} // namespace nesshi::assembler
