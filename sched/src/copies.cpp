// `#copy` in .pk sources: a block of lines written once and instantiated with names swapped
// (the IC kernel's B bodies are its A bodies with the payload buffers exchanged).
#include "sched/block.hpp"

#include "text.hpp"

#include "base/error.hpp"

#include <fmt/core.h>

#include <cctype>
#include <map>
#include <regex>
#include <utility>

namespace nesshi::sched {

namespace {

// One `X = Y` of a `#copy NAME:` line: whole words equal to X become Y and those equal to Y become
// X; `*_A = *_B` exchanges the suffixes of identifiers instead; `f30-f46 = f50-f66` pairs the ranges
// register by register.
struct Swaps {
    std::map<std::string, std::string> words;
    std::vector<std::pair<std::string, std::string>> suffixes;

    void word(const std::string& a, const std::string& b) {
        words[a] = b;
        words[b] = a;
    }
    std::string apply(const std::string& w) const {
        if (const auto it = words.find(w); it != words.end()) return it->second;
        for (const auto& [a, b] : suffixes) {
            if (w.size() > a.size() && w.ends_with(a)) return w.substr(0, w.size() - a.size()) + b;
            if (w.size() > b.size() && w.ends_with(b)) return w.substr(0, w.size() - b.size()) + a;
        }
        return w;
    }
};

// "f30-f46" as its register names, or {text} for a single word.
std::vector<std::string> range_words(const std::string& text) {
    static const std::regex range(R"(([a-z])(\d+)-([a-z])(\d+))");
    std::smatch m;
    if (!std::regex_match(text, m, range) || m[1] != m[3]) return {text};
    std::vector<std::string> out;
    for (int r = std::stoi(m[2]); r <= std::stoi(m[4]); ++r) out.push_back(m[1].str() + std::to_string(r));
    return out;
}

Swaps parse_swaps(const std::string& list, std::string_view filename, int line) {
    static const std::regex ident(R"([A-Za-z_][A-Za-z0-9_]*)"), suffix(R"(\*([A-Za-z0-9_]+))");
    Swaps s;
    std::size_t start = 0;
    while (start <= list.size()) {
        std::size_t comma = list.find(',', start);
        if (comma == std::string::npos) comma = list.size();
        const std::string pair = trim(std::string_view(list).substr(start, comma - start));
        start = comma + 1;
        const std::size_t eq = pair.find('=');
        auto bad = [&](const std::string& why) {
            return base::Error(base::SourceLoc(filename, line), fmt::format("'#copy': {} in '{}'", why, pair));
        };
        if (eq == std::string::npos) throw bad("each swap is 'X = Y'");
        const std::string a = trim(std::string_view(pair).substr(0, eq)), b = trim(std::string_view(pair).substr(eq + 1));
        std::smatch ma, mb;
        if (std::regex_match(a, ma, suffix) && std::regex_match(b, mb, suffix)) {
            s.suffixes.emplace_back(ma[1].str(), mb[1].str());
            continue;
        }
        const std::vector<std::string> ra = range_words(a), rb = range_words(b);
        if (ra.size() != rb.size()) throw bad(fmt::format("{} registers against {}", ra.size(), rb.size()));
        for (std::size_t k = 0; k < ra.size(); ++k) {
            if (!std::regex_match(ra[k], ident) || !std::regex_match(rb[k], ident))
                throw bad("a swap names words, register ranges (f30-f46) or suffixes (*_A)");
            s.word(ra[k], rb[k]);
        }
    }
    return s;
}

// `line` with every word of its code swapped; its comment as written.
std::string swapped(const std::string& line, const Swaps& s) {
    const std::size_t hash = line.find('#');
    const std::string code = line.substr(0, hash);
    std::string out;
    for (std::size_t i = 0; i < code.size();) {
        const auto word_char = [&](std::size_t k) {
            return std::isalnum(static_cast<unsigned char>(code[k])) || code[k] == '_';
        };
        if (!word_char(i) || (i > 0 && (word_char(i - 1) || code[i - 1] == '%'))) {
            out += code[i++];
            continue;
        }
        std::size_t j = i;
        while (j < code.size() && word_char(j)) ++j;
        out += s.apply(code.substr(i, j - i));
        i = j;
    }
    return hash == std::string::npos ? out : out + line.substr(hash);
}

} // namespace

namespace {

// One `#copy NAME:` line: the block it copies ([first, last) line index) and its own line.
struct Copy {
    std::string name;
    std::size_t first = 0, last = 0;
    int line = 0;
};

std::string expand(std::string_view text, std::string_view filename, std::vector<Copy>* made) {
    const std::vector<std::string> lines = split_lines(text);
    std::map<std::string, std::pair<std::size_t, std::size_t>> blocks; // name -> [first, last) line index
    std::string open;
    std::size_t opened = 0;
    std::string out, copies;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string t = trim(lines[i]);
        const int ln = static_cast<int>(i + 1);
        if (t.starts_with("#copy begin")) {
            if (!open.empty()) throw base::Error(base::SourceLoc(filename, ln), "'#copy begin' inside another (they do not nest)");
            open = strip_comment(std::string_view(t).substr(std::string_view("#copy begin").size()));
            if (open.empty()) throw base::Error(base::SourceLoc(filename, ln), "'#copy begin' names its block: '#copy begin NAME'");
            if (blocks.count(open)) throw base::Error(base::SourceLoc(filename, ln), fmt::format("a second '#copy begin {}'", open));
            opened = i;
            out += '\n'; // blank: every line keeps its number
            continue;
        }
        if (t.starts_with("#copy end") && strip_comment(std::string_view(t).substr(9)).empty()) {
            if (open.empty()) throw base::Error(base::SourceLoc(filename, ln), "'#copy end' without '#copy begin'");
            blocks[open] = {opened + 1, i};
            open.clear();
            out += '\n';
            continue;
        }
        if (t.starts_with("#copy ")) {
            const std::string d = "#copy " + strip_comment(std::string_view(t).substr(6));
            const std::size_t colon = d.find(':');
            const std::string name = trim(std::string_view(d).substr(6, colon == std::string::npos ? std::string::npos : colon - 6));
            const auto it = blocks.find(name);
            if (it == blocks.end())
                throw base::Error(base::SourceLoc(filename, ln),
                                  fmt::format("'#copy {}' names no block closed before it ('#copy begin {}' ... '#copy end')", name, name));
            const Swaps s = colon == std::string::npos ? Swaps{} : parse_swaps(d.substr(colon + 1), filename, ln);
            // The copy goes after the file's last line, so that no line written in the file
            // changes its number.
            copies += fmt::format("# ---- lines {}-{} copied by '#copy {}' (line {}) ----\n", it->second.first + 1,
                                  it->second.second, name, ln);
            for (std::size_t k = it->second.first; k < it->second.second; ++k) copies += swapped(lines[k], s) + '\n';
            if (made) made->push_back({name, it->second.first, it->second.second, ln});
            out += '\n';
            continue;
        }
        out += lines[i] + '\n';
    }
    if (!open.empty()) throw base::Error(base::SourceLoc(filename, static_cast<int>(opened + 1)), "'#copy begin' is never closed by '#copy end'");
    return out + copies;
}

} // namespace

std::string expand_copies(std::string_view text, std::string_view filename) { return expand(text, filename, nullptr); }

namespace {

// Where each line a copy appended to `text` comes from: the copy, and the line it copies (0 for the
// copy's header comment); none for a line written in the file.
class CopyOrigins {
  public:
    CopyOrigins(std::string_view text, std::string_view filename) : written_(static_cast<int>(split_lines(text).size())) {
        try {
            (void)expand(text, filename, &copies_);
        } catch (const base::Error&) {
            copies_.clear(); // the caller reports the error itself
        }
    }
    bool any() const { return !copies_.empty(); }
    std::pair<const Copy*, int> operator()(int line) const {
        int at = written_ + 1;
        for (const Copy& c : copies_) {
            const int n = static_cast<int>(c.last - c.first);
            if (line == at) return {&c, 0};
            if (line > at && line <= at + n) return {&c, static_cast<int>(c.first) + (line - at)};
            at += n + 1;
        }
        return {nullptr, 0};
    }

  private:
    int written_;
    std::vector<Copy> copies_;
};

} // namespace

int written_line(std::string_view text, std::string_view filename, int line) {
    const auto [copy, from] = CopyOrigins(text, filename)(line);
    return copy ? from : line;
}

std::string copied_lines_named(const std::string& diagnostics, std::string_view text, std::string_view filename) {
    const CopyOrigins origin(text, filename);
    if (!origin.any()) return diagnostics;
    static const std::regex at_line(R"(:(\d+)(:\d+)?:)");
    const std::string prefix(filename);
    std::string out;
    std::size_t pos = 0;
    while (pos < diagnostics.size()) {
        std::size_t eol = diagnostics.find('\n', pos);
        if (eol == std::string::npos) eol = diagnostics.size();
        std::string line = diagnostics.substr(pos, eol - pos);
        std::smatch m;
        const std::size_t hit = line.find(prefix + ":");
        if (hit != std::string::npos) {
            const std::string rest = line.substr(hit + prefix.size());
            if (std::regex_search(rest, m, at_line) && m.position(0) == 0) {
                const auto [copy, from] = origin(std::stoi(m[1]));
                if (copy && from > 0)
                    line = line.substr(0, hit + prefix.size()) + ":" + std::to_string(from) + m[2].str() + ":" +
                           rest.substr(static_cast<std::size_t>(m.length(0))) +
                           fmt::format(" [in the copy made by '#copy {}' at line {}]", copy->name, copy->line);
            }
        }
        out += line;
        if (eol < diagnostics.size()) out += '\n';
        pos = eol + 1;
    }
    return out;
}

} // namespace nesshi::sched
