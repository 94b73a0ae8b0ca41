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
    if (std::stoi(m[2]) > std::stoi(m[4])) return {}; // a range runs upwards: the caller says so
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
        if (ra.empty() || rb.empty()) throw bad("a register range runs upwards (f30-f46)");
        if (ra.size() != rb.size()) throw bad(fmt::format("{} registers against {}", ra.size(), rb.size()));
        for (std::size_t k = 0; k < ra.size(); ++k) {
            if (!std::regex_match(ra[k], ident) || !std::regex_match(rb[k], ident))
                throw bad("a swap names words, register ranges (f30-f46) or suffixes (*_A)");
            if (s.words.count(ra[k]) || s.words.count(rb[k]) || ra[k] == rb[k])
                throw bad(fmt::format("'{}' or '{}' is swapped twice", ra[k], rb[k]));
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
    // Most sources have no #copy, and pack_source expands every text legalize tries: return them as
    // they are (the same as splitting and joining when the last line ends).
    if (text.find("#copy") == std::string_view::npos && (text.empty() || text.back() == '\n')) return std::string(text);
    const std::vector<std::string> lines = split_lines(text);
    std::map<std::string, std::pair<std::size_t, std::size_t>> blocks; // name -> [first, last) line index
    std::string open;
    std::size_t opened = 0;
    std::string out, copies;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string t = trim(lines[i]);
        const int ln = static_cast<int>(i + 1);
        if (!t.starts_with("#copy") || (t.size() > 5 && !std::isspace(static_cast<unsigned char>(t[5])))) {
            out += lines[i] + '\n';
            continue;
        }
        const std::string rest = strip_comment(std::string_view(t).substr(5)); // "begin NAME", "end", "NAME: swaps"
        const std::string word = rest.substr(0, rest.find_first_of(" \t:"));
        auto fail = [&](const std::string& why) { return base::Error(base::SourceLoc(filename, ln), why); };
        out += '\n'; // a marker line goes blank: every line keeps its number
        if (word == "begin") {
            if (!open.empty()) throw fail("'#copy begin' inside another (they do not nest)");
            open = trim(std::string_view(rest).substr(5));
            if (open.empty()) throw fail("'#copy begin' names its block: '#copy begin NAME'");
            if (blocks.count(open)) throw fail(fmt::format("a second '#copy begin {}'", open));
            opened = i;
            continue;
        }
        if (rest == "end") {
            if (open.empty()) throw fail("'#copy end' without '#copy begin'");
            blocks[open] = {opened + 1, i};
            open.clear();
            continue;
        }
        if (!open.empty()) throw fail(fmt::format("a '#copy' inside the block '{}' it would copy from (copy after '#copy end')", open));
        const std::size_t colon = rest.find(':');
        const std::string name = trim(std::string_view(rest).substr(0, colon));
        const auto it = blocks.find(name);
        if (it == blocks.end())
            throw fail(fmt::format("'#copy {}' names no block closed before it ('#copy begin {}' ... '#copy end')", name, name));
        const Swaps sw = colon == std::string::npos ? Swaps{} : parse_swaps(rest.substr(colon + 1), filename, ln);
        // The copy goes after the file's last line, so that no line written in the file changes
        // its number.
        copies += fmt::format("# ---- lines {}-{} copied by '#copy {}' (line {}) ----\n", it->second.first + 1, it->second.second,
                              name, ln);
        for (std::size_t k = it->second.first; k < it->second.second; ++k) copies += swapped(lines[k], sw) + '\n';
        if (made) made->push_back({name, it->second.first, it->second.second, ln});
    }
    if (!open.empty()) throw base::Error(base::SourceLoc(filename, static_cast<int>(opened + 1)), "'#copy begin' is never closed by '#copy end'");
    return out + copies;
}

} // namespace

std::string expand_copies(std::string_view text, std::string_view filename) { return expand(text, filename, nullptr); }

CopiedLines::CopiedLines(std::string_view text, std::string_view filename)
    : filename_(filename) {
    std::vector<Copy> made;
    try {
        (void)expand(text, filename, &made);
    } catch (const base::Error&) {
        return; // the caller reports the error itself
    }
    int at = static_cast<int>(split_lines(text).size()) + 1; // each copy: its header comment, then its lines
    for (const Copy& c : made) {
        spans_.push_back({at, static_cast<int>(c.first), static_cast<int>(c.last - c.first), c.name, c.line});
        at += static_cast<int>(c.last - c.first) + 1;
    }
}

std::optional<CopiedLines::Origin> CopiedLines::operator()(int line) const {
    for (const Span& s : spans_)
        if (line > s.at && line <= s.at + s.count) return Origin{s.first + (line - s.at), s.name, s.line};
    return std::nullopt;
}

std::string CopiedLines::named(const std::string& diagnostics) const {
    if (spans_.empty()) return diagnostics;
    static const std::regex at_line(R"(:(\d+)(:\d+)?:)");
    std::string out;
    std::size_t pos = 0;
    while (pos < diagnostics.size()) {
        std::size_t eol = diagnostics.find('\n', pos);
        if (eol == std::string::npos) eol = diagnostics.size();
        std::string line = diagnostics.substr(pos, eol - pos);
        const std::size_t hit = line.find(filename_ + ":");
        if (hit != std::string::npos) {
            const std::string rest = line.substr(hit + filename_.size());
            std::smatch m;
            if (std::regex_search(rest, m, at_line) && m.position(0) == 0)
                if (const std::optional<Origin> o = (*this)(std::stoi(m[1])))
                    line = line.substr(0, hit + filename_.size()) + ":" + std::to_string(o->line) + m[2].str() + ":" +
                           rest.substr(static_cast<std::size_t>(m.length(0))) + o->note();
        }
        out += line;
        if (eol < diagnostics.size()) out += '\n';
        pos = eol + 1;
    }
    return out;
}

std::string CopiedLines::Origin::note() const { return fmt::format(" [in the copy made by '#copy {}' at line {}]", copy, copy_line); }

} // namespace nesshi::sched
