// First pass (see layout.hpp).
#include "layout.hpp"

#include "base/suggest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace nesshi::assembler {

namespace {
constexpr size_t kAll = std::numeric_limits<size_t>::max();
constexpr uint64_t kMaxSpace = 1u << 26; // 64 MB: larger than any memory of the presets

Loc arg_loc(const DirectiveRec& d, size_t i) { return i < d.arg_locs.size() ? d.arg_locs[i] : d.loc; }

bool is_pow2(int64_t v) { return v > 0 && (v & (v - 1)) == 0; }

// The links of a failing chain named in its message: "'a' has no value: 'b' has no value: ...".
// Past the first few, the message gives the reason at the end of the chain, not every link.
constexpr int kNamedLinks = 8;
} // namespace

void Layout::define(const std::string& name, SymbolDef def) {
    auto [it, inserted] = symbols.try_emplace(name, def);
    if (inserted) return;
    Diagnostic& d = diags_.error(def.loc, fmt::format("'{}' is already defined", name));
    Diagnostics::note(d, it->second.loc, "previous definition is here");
}

std::vector<std::string> Layout::symbol_names() const {
    std::vector<std::string> names;
    for (const auto& [name, def] : symbols) names.push_back(name);
    return names;
}

std::optional<int64_t> Layout::lookup(const Token& name, std::string& err, size_t limit) {
    auto it = symbols.find(name.text);
    if (it == symbols.end() || (limit != kAll && it->second.order > limit)) {
        err = limit != kAll ? fmt::format("'{}' is undefined here (.data, .space, .align and .loc need "
                                          "values known where they stand)", name.text)
                            : fmt::format("undefined symbol '{}'{}", name.text, base::did_you_mean(name.text, symbol_names()));
        return std::nullopt;
    }
    SymbolDef& s = it->second;
    if (s.kind != SymbolDef::Kind::Equ) {
        deps_ = std::max(deps_, s.order);
        return s.value;
    }
    // Known, and known here: every definition the value needs comes before `limit`.
    if (s.state == 2 && (limit == kAll || s.deps <= limit)) {
        deps_ = std::max(deps_, s.deps);
        return s.value;
    }
    if (s.state == 3) {
        err = fmt::format("'{}' has no value: {}", name.text, s.error);
        return std::nullopt;
    }
    if (s.state == 1) {
        err = fmt::format("'{}' is defined in terms of itself", name.text);
        return std::nullopt;
    }
    return evaluate_equ(name, s, err, limit);
}

std::optional<int64_t> Layout::evaluate_equ(const Token& name, SymbolDef& s, std::string& err, size_t limit) {
    const int before = s.state; // 0, or 2 when the value needs definitions after `limit`
    const size_t outer_deps = deps_;
    const int level = equ_depth_++;
    s.state = 1;
    deps_ = s.order;
    ExprResult r = eval_expr(s.expr, [&](const Token& t, std::string& e) { return lookup(t, e, limit); }, &nesting_);
    --equ_depth_;
    const size_t deps = deps_;
    deps_ = std::max(outer_deps, deps);
    if (r.ok) {
        // The same value wherever it is known (a name's value does not depend on where it is
        // asked for, only whether it is known there), so it is kept.
        s.state = 2;
        s.value = r.value;
        s.deps = deps;
        return r.value;
    }
    // Known elsewhere, not here: keep the value for later; or failed for good (second pass); or
    // unknown here, to be tried again where it is used next.
    s.state = before == 2 ? 2 : limit == kAll ? 3 : 0;
    s.error = r.error;
    if (level >= kNamedLinks) { // a deep link of a long chain: pass the reason on
        elided_ = true;
        err = r.error;
    } else if (level == kNamedLinks - 1 && elided_) {
        elided_ = false;
        err = fmt::format("'{}' has no value: ...: {}", name.text, r.error);
    } else {
        err = fmt::format("'{}' has no value: {}", name.text, r.error);
    }
    return std::nullopt;
}

Resolver Layout::resolver() {
    return [this](const Token& t, std::string& err) { return lookup(t, err, kAll); };
}

std::optional<int64_t> Layout::eval_now(const std::vector<Token>& toks, Loc loc, size_t limit) {
    ExprResult r = eval_expr(toks, [&](const Token& t, std::string& e) { return lookup(t, e, limit); }, &nesting_);
    if (!r.ok) {
        diags_.error(Loc{loc.file, loc.line, r.col ? r.col : loc.col}, r.error);
        return std::nullopt;
    }
    return r.value;
}

DataSec* Layout::current_data(Loc loc) {
    if (!in_data_) {
        diags_.error(loc, "data directive outside .data (use .data [ADDR] first)");
        return nullptr;
    }
    if (data_index_ < 0) {
        DataSec s;
        s.address = m_.memories.empty() ? 0 : m_.memories.front().base;
        s.loc = loc;
        data.push_back(s);
        data_index_ = int(data.size()) - 1;
    }
    return &data[size_t(data_index_)];
}

void Layout::directive(const DirectiveRec& d, size_t order) {
    const std::string& n = d.name;
    auto want_args = [&](size_t lo, size_t hi, std::string_view usage) {
        if (d.args.size() >= lo && d.args.size() <= hi) {
            for (size_t i = 0; i < d.args.size(); ++i)
                if (d.args[i].empty()) {
                    diags_.error(arg_loc(d, i), fmt::format("missing operand; usage: {}", usage));
                    return false;
                }
            return true;
        }
        diags_.error(d.loc, fmt::format("usage: {}", usage));
        return false;
    };
    if (n == ".text") {
        if (want_args(0, 0, ".text")) in_data_ = false;
    } else if (n == ".data") {
        if (!want_args(0, 1, ".data [ADDRESS]")) return;
        in_data_ = true;
        if (d.args.empty()) return;
        auto v = eval_now(d.args[0], arg_loc(d, 0), order);
        if (!v) return;
        if (*v < 0 || *v > int64_t(UINT32_MAX)) {
            diags_.error(arg_loc(d, 0), fmt::format("data address {} outside the 32-bit address space", *v));
            return;
        }
        DataSec s;
        s.address = uint32_t(*v);
        s.loc = d.loc;
        data.push_back(s);
        data_index_ = int(data.size()) - 1;
    } else if (n == ".word" || n == ".half" || n == ".byte" || n == ".float") {
        if (!want_args(1, kAll, fmt::format("{} VALUE[, VALUE...]", n))) return;
        DataSec* s = current_data(d.loc);
        if (!s) return;
        uint64_t width = n == ".half" ? 2 : n == ".byte" ? 1 : 4;
        fills.push_back({&d, size_t(data_index_), s->size});
        s->size += width * d.args.size();
    } else if (n == ".space" || n == ".align") {
        bool space = n == ".space";
        if (!want_args(1, 1, space ? ".space BYTES" : ".align BYTES (a power of two)")) return;
        DataSec* s = current_data(d.loc);
        if (!s) return;
        auto v = eval_now(d.args[0], arg_loc(d, 0), order);
        if (!v) return;
        if (space && (*v < 0 || uint64_t(*v) > kMaxSpace)) {
            diags_.error(arg_loc(d, 0), fmt::format(".space size {} out of range (0..{})", *v, kMaxSpace));
            return;
        }
        if (!space && (!is_pow2(*v) || *v > 4096)) {
            diags_.error(arg_loc(d, 0), fmt::format(".align needs a power of two up to 4096, found {}", *v));
            return;
        }
        if (space) s->size += uint64_t(*v);
        else {
            uint64_t a = uint64_t(*v), addr = s->address + s->size;
            s->size += (a - addr % a) % a;
        }
    } else if (n == ".equ") {
        if (!want_args(2, 2, ".equ NAME, EXPRESSION")) return;
        if (d.args[0].size() != 1 || d.args[0][0].kind != Tok::Ident) {
            diags_.error(arg_loc(d, 0), ".equ expects a name first");
            return;
        }
        SymbolDef s;
        s.kind = SymbolDef::Kind::Equ;
        s.loc = arg_loc(d, 0);
        s.order = order;
        s.expr = d.args[1];
        define(d.args[0][0].text, s);
    } else if (n == ".global") {
        if (!want_args(1, kAll, ".global NAME[, NAME...]")) return;
        globals.push_back(&d);
    } else if (n == ".file") {
        if (!want_args(1, 1, ".file \"NAME\"")) return;
        if (d.args[0].size() != 1 || d.args[0][0].kind != Tok::String || d.args[0][0].text.empty()) {
            diags_.error(arg_loc(d, 0), ".file expects a file name in double quotes");
            return;
        }
        logical_file_ = d.args[0][0].text;
    } else if (n == ".loc") {
        if (!want_args(1, 1, ".loc LINE")) return;
        auto v = eval_now(d.args[0], arg_loc(d, 0), order);
        if (!v) return;
        if (*v < 0 || *v > int64_t(UINT32_MAX)) {
            diags_.error(arg_loc(d, 0), fmt::format(".loc line {} out of range", *v));
            return;
        }
        pending_loc_ = *v;
    }
}

void Layout::run(std::vector<Item>& items) {
    for (size_t order = 0; order < items.size(); ++order) {
        Item& it = items[order];
        switch (it.kind) {
        case Item::Kind::Label: {
            SymbolDef s;
            s.loc = it.label.loc;
            s.order = order;
            if (in_data_) {
                DataSec* d = current_data(it.label.loc);
                if (!d) break;
                s.kind = SymbolDef::Kind::Data;
                s.value = int64_t(d->address + d->size);
            } else {
                s.kind = SymbolDef::Kind::Code;
                s.value = int64_t(bundles.size());
            }
            define(it.label.name, s);
            break;
        }
        case Item::Kind::Directive: directive(it.directive, order); break;
        case Item::Kind::Bundle: {
            if (in_data_) {
                diags_.error(it.bundle.loc, "operation in a .data section (use .text first)");
                break;
            }
            PlacedBundle b{&it.bundle, logical_file_, uint32_t(it.bundle.loc.line)};
            if (b.file.empty()) b.file = sources_.files[size_t(it.bundle.loc.file)].name;
            if (pending_loc_ >= 0) b.line = uint32_t(pending_loc_);
            pending_loc_ = -1;
            bundles.push_back(std::move(b));
            break;
        }
        }
    }
    // Data sections: inside the address space and not overlapping.
    std::vector<size_t> order(data.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return data[a].address < data[b].address; });
    for (size_t k = 0; k < order.size(); ++k) {
        const DataSec& s = data[order[k]];
        if (s.address + s.size > (uint64_t{1} << 32))
            diags_.error(s.loc, "data section runs past the end of the 32-bit address space");
        else if (s.size > kMaxSection)
            diags_.error(s.loc, fmt::format("data section of {} bytes is larger than the {} MB the "
                                            "assembler accepts", s.size, kMaxSection >> 20));
        if (k == 0 || s.size == 0) continue;
        for (size_t j = 0; j < k; ++j) {
            const DataSec& p = data[order[j]];
            if (p.size && p.address + p.size > s.address) {
                Diagnostic& d = diags_.error(s.loc, fmt::format("data at 0x{:x} overlaps earlier data "
                                                                "(0x{:x}..0x{:x})", s.address, p.address,
                                                                p.address + p.size - 1));
                Diagnostics::note(d, p.loc, "the earlier data section starts here");
                break;
            }
        }
    }
}

} // namespace nesshi::assembler
