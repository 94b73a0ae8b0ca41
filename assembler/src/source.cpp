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
    if (stopped_ || (error_limit_ > 0 && errors_ >= error_limit_)) {
        stopped_ = true;
        dropped_ = {};
        return dropped_;
    }
    ++errors_;
    list_.push_back({Severity::Error, loc, std::move(message), {}});
    return list_.back();
}

Diagnostic& Diagnostics::warning(Loc loc, std::string message) {
    if (stopped_) {
        dropped_ = {};
        return dropped_;
    }
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
    if (d.loc.file < 0) return fmt::format("{}: {}\n", word, d.message);
    if (d.loc.line <= 0) // the file as a whole
        return fmt::format("{}: {}: {}\n", sources_.files[size_t(d.loc.file)].name, word, d.message);
    std::string out = fmt::format("{}:{}:{}: {}: {}\n", sources_.files[size_t(d.loc.file)].name,
                                  d.loc.line, d.loc.col, word, d.message);
    const std::string_view line = sources_.line(d.loc);
    const size_t caret = std::min(size_t(std::max(d.loc.col, 1) - 1), line.size());
    // A long line is cut to kMaxShownLine characters around the caret (never inside a UTF-8
    // sequence), so a diagnostic costs a bounded number of bytes however long the line.
    size_t begin = 0, end = line.size();
    if (line.size() > kMaxShownLine) {
        begin = caret > kMaxShownLine / 2 ? caret - kMaxShownLine / 2 : 0;
        end = std::min(line.size(), begin + kMaxShownLine);
        begin = end - kMaxShownLine;
        auto continuation = [&](size_t i) { return i < line.size() && (uint8_t(line[i]) & 0xc0) == 0x80; };
        while (begin < caret && continuation(begin)) ++begin;
        while (end > caret && continuation(end)) --end;
    }
    const std::string_view cut_before = begin > 0 ? "..." : "", cut_after = end < line.size() ? "..." : "";
    const std::string_view text = line.substr(begin, end - begin);
    out += cut_before;
    out += text;
    out += cut_after;
    out += '\n';
    // Keep tabs so the caret lines up with the source line in any terminal.
    out.append(cut_before.size(), ' ');
    for (size_t i = 0; begin + i < caret; ++i) out += text[i] == '\t' ? '\t' : ' ';
    out += "^\n";
    return out;
}

std::vector<const Diagnostic*> Diagnostics::in_order() const {
    // In source order (the passes find problems in different orders); ties keep discovery order.
    std::vector<const Diagnostic*> sorted;
    for (const auto& d : list_) sorted.push_back(&d);
    std::stable_sort(sorted.begin(), sorted.end(), [](const Diagnostic* a, const Diagnostic* b) {
        return std::tie(a->loc.file, a->loc.line, a->loc.col) < std::tie(b->loc.file, b->loc.line, b->loc.col);
    });
    return sorted;
}

std::string Diagnostics::render() const {
    const std::vector<const Diagnostic*> sorted = in_order();
    std::string out;
    for (const Diagnostic* p : sorted) {
        const Diagnostic& d = *p;
        out += render_one(d);
        for (const auto& n : d.notes) out += render_one(n);
    }
    if (stopped_) out += "fatal error: too many errors emitted, stopping now\n";
    return out;
}

} // namespace nesshi::assembler
