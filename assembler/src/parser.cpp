// The line parser (see parser.hpp).
#include "parser.hpp"

#include "operands.hpp"

#include "base/error.hpp"
#include "base/read_file.hpp"
#include "base/suggest.hpp"

#include <fmt/format.h>

#include <array>
#include <filesystem>

namespace nesshi::assembler {

namespace {
constexpr int kMaxIncludeDepth = 16;

std::vector<std::vector<Token>> split_args(std::span<const Token> toks, std::vector<int>& cols) {
    std::vector<std::vector<Token>> out;
    if (toks.empty()) return out;
    int depth = 0;
    out.emplace_back();
    cols.push_back(toks[0].col);
    for (size_t i = 0; i < toks.size(); ++i) {
        const Token& t = toks[i];
        if (t.is("(")) ++depth;
        if (t.is(")")) --depth;
        if (depth == 0 && t.is(",")) {
            out.emplace_back();
            cols.push_back(i + 1 < toks.size() ? toks[i + 1].col : t.col + 1);
            continue;
        }
        out.back().push_back(t);
    }
    return out;
}

// An include candidate: false when there is no file at `path` or it is a directory (the search
// goes on); a path that names something else read_file refuses (a device, a pipe, a file above
// the cap) throws base::Error.
bool read_text(const std::string& path, std::string& text) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec) || std::filesystem::is_directory(path, ec)) return false;
    text = base::read_file(path);
    return true;
}
} // namespace

constexpr std::array<std::string_view, 16> kDirectives = {
    ".text", ".data", ".word", ".half", ".byte", ".float", ".space", ".align",
    ".equ", ".include", ".global", ".globl", ".file", ".loc", ".section", ".end"};

bool known_directive(std::string_view name) {
    for (auto n : kDirectives)
        if (n == name && n != ".section" && n != ".end") return true;
    return false;
}

void Parser::parse_file(int file, int depth) {
    int nlines = int(sources_.files[size_t(file)].lines.size());
    for (int l = 1; l <= nlines && !diags_.stopped(); ++l) parse_line(file, l, depth);
    close_open_bundle();
}

void Parser::close_open_bundle() {
    if (!in_bundle_) return;
    diags_.error(bundle_.loc, "unterminated bundle: missing '}'");
    in_bundle_ = false;
    bundle_ = {};
}

void Parser::parse_line(int file, int line, int depth) {
    // Copy: an .include below may add files and move the line storage.
    std::string text(sources_.files[size_t(file)].lines[size_t(line - 1)]);
    std::vector<Token> toks = lex_line(text);
    size_t i = 0;
    while (i < toks.size() && !diags_.stopped()) {
        const Token& t = toks[i];
        Loc loc{file, line, t.col};
        if (t.kind == Tok::Bad) {
            diags_.error(loc, t.text);
            if (in_bundle_) bundle_.had_errors = true;
            return;
        }
        if (in_bundle_) {
            if (t.is("}")) {
                in_bundle_ = false;
                if (bundle_.ops.empty() && !bundle_.had_errors) diags_.error(bundle_.loc, "empty bundle");
                else items.push_back({Item::Kind::Bundle, {}, {}, std::move(bundle_)});
                bundle_ = {};
                ++i;
                continue;
            }
            if (t.is(";")) {
                ++i;
                continue;
            }
            if (t.is("{")) {
                diags_.error(loc, "'{' inside a bundle (bundles do not nest)");
                bundle_.had_errors = true;
                ++i;
                continue;
            }
            if (t.kind == Tok::Ident && !t.text.empty() && t.text[0] == '.') {
                diags_.error(loc, fmt::format("directive '{}' inside a bundle", t.text));
                bundle_.had_errors = true;
                return;
            }
            i = parse_op_at(toks, i, file, line, true);
            continue;
        }
        bool next_colon = i + 1 < toks.size() && toks[i + 1].is(":");
        if (t.kind == Tok::Ident && next_colon && m_.slot_index(t.text) < 0) {
            if (is_register_name(t.text)) diags_.error(loc, fmt::format("'{}' is a register name and cannot be a label", t.text));
            else if (t.text[0] == '.' && known_directive(t.text))
                diags_.error(loc, fmt::format("'{}' is a directive name and cannot be a label", t.text));
            else items.push_back({Item::Kind::Label, {loc, t.text}, {}, {}});
            i += 2;
            continue;
        }
        if (t.is("{")) {
            in_bundle_ = true;
            bundle_ = {};
            bundle_.loc = loc;
            ++i;
            continue;
        }
        if (t.kind == Tok::Ident && t.text[0] == '.' && !next_colon) {
            directive(toks, i, file, line, depth);
            return;
        }
        if (t.is("}")) {
            diags_.error(loc, "'}' without a matching '{'");
            ++i;
            continue;
        }
        if (t.is(";")) {
            diags_.error(loc, "';' outside a bundle: group operations with { op ; op }");
            ++i;
            continue;
        }
        i = parse_op_at(toks, i, file, line, false);
    }
}

// Parses one operation starting at toks[i]; returns the index after it.
size_t Parser::parse_op_at(const std::vector<Token>& toks, size_t i, int file, int line, bool in_bundle) {
    size_t start = i, end = i;
    while (end < toks.size() && !toks[end].is(";") && !toks[end].is("}") && !toks[end].is("{")) ++end;
    if (!in_bundle && end < toks.size()) {
        if (toks[end].is(";"))
            diags_.error({file, line, toks[end].col},
                         "';' outside a bundle: group operations with { op ; op }");
        else
            diags_.error({file, line, toks[end].col},
                         fmt::format("unexpected '{}' after an operation", toks[end].text));
    }
    std::span<const Token> op(toks.data() + start, end - start);
    int pin = -1;
    Loc loc{file, line, toks[start].col};
    bool ok = true;
    if (op.size() >= 2 && op[0].kind == Tok::Ident && op[1].is(":")) {
        pin = m_.slot_index(op[0].text);
        if (pin < 0) {
            std::string names;
            for (const auto& s : m_.slots) names += (names.empty() ? "" : ", ") + s.name;
            diags_.error(loc, in_bundle ? fmt::format("'{}' is not an issue slot of {} (slots: {}); "
                                                      "labels go before the bundle",
                                                      op[0].text, m_.name, names)
                                        : fmt::format("'{}' is not an issue slot of {} (slots: {})",
                                                      op[0].text, m_.name, names));
            ok = false;
        }
        op = op.subspan(2);
    }
    if (ok && op.empty()) {
        diags_.error(loc, "expected an operation after the slot name");
        ok = false;
    }
    std::optional<OpRec> rec;
    if (ok) rec = parse_op(op, file, line, m_, diags_);
    if (rec) {
        rec->loc = loc;
        rec->pin = pin;
        const Token& last = toks[end - 1];
        const std::string& src = sources_.files[size_t(file)].lines[size_t(line - 1)];
        size_t from = size_t(loc.col - 1), to = size_t(last.col - 1) + last.text.size();
        rec->text = src.substr(from, std::min(src.size(), to) - from);
    }
    if (in_bundle) {
        if (rec) bundle_.ops.push_back(std::move(*rec));
        else bundle_.had_errors = true;
    } else {
        BundleRec b;
        b.loc = loc;
        if (rec) b.ops.push_back(std::move(*rec));
        else b.had_errors = true;
        items.push_back({Item::Kind::Bundle, {}, {}, std::move(b)});
    }
    if (!in_bundle) return toks.size();
    return end;
}

void Parser::directive(const std::vector<Token>& toks, size_t i, int file, int line, int depth) {
    const Token& name = toks[i];
    Loc loc{file, line, name.col};
    if (!known_directive(name.text)) {
        std::vector<std::string> names;
        for (auto n : kDirectives)
            if (known_directive(n)) names.emplace_back(n);
        diags_.error(loc, fmt::format("unknown directive '{}'{}", name.text, base::did_you_mean(name.text, names)));
        return;
    }
    std::span<const Token> rest(toks.data() + i + 1, toks.size() - i - 1);
    for (const auto& t : rest)
        if (t.kind == Tok::Bad) {
            diags_.error({file, line, t.col}, t.text);
            return;
        }
    if (name.text == ".include") {
        if (rest.size() != 1 || rest[0].kind != Tok::String) {
            diags_.error(loc, ".include expects a file name in double quotes");
            return;
        }
        include(rest[0], loc, file, depth);
        return;
    }
    DirectiveRec d;
    d.loc = loc;
    d.name = name.text == ".globl" ? ".global" : name.text;
    std::vector<int> cols;
    d.args = split_args(rest, cols);
    for (int c : cols) d.arg_locs.push_back({file, line, c});
    items.push_back({Item::Kind::Directive, {}, std::move(d), {}});
}

void Parser::include(const Token& name, Loc loc, int file, int depth) {
    if (depth + 1 > kMaxIncludeDepth) {
        diags_.error(loc, fmt::format(".include nested more than {} deep (a cycle?)", kMaxIncludeDepth));
        return;
    }
    std::vector<std::string> candidates;
    if (!name.text.empty() && name.text[0] == '/') candidates.push_back(name.text);
    else {
        candidates.push_back(sources_.files[size_t(file)].dir + name.text);
        for (const auto& d : opts_.include_dirs)
            candidates.push_back(d.empty() || d.back() == '/' ? d + name.text : d + "/" + name.text);
    }
    std::string text;
    for (auto path : candidates) {
        if (opts_.read_file) {
            path = std::filesystem::path(path).lexically_normal().generic_string();
            if (!opts_.read_file(path, text)) continue;
        } else {
            try {
                if (!read_text(path, text)) continue;
            } catch (const base::Error& e) {
                diags_.error(loc, fmt::format("cannot include \"{}\": {}: {}", name.text, e.loc().str(), e.message()));
                return;
            }
        }
        // The bundle state belongs to the including file.
        bool saved_in = in_bundle_;
        in_bundle_ = false;
        int id = sources_.add(path, text);
        parse_file(id, depth + 1);
        in_bundle_ = saved_in;
        return;
    }
    diags_.error(loc, fmt::format("cannot find include file \"{}\"", name.text));
}

} // namespace nesshi::assembler
