// Data filling and object building (see emit.hpp).
#include "emit.hpp"

#include "operands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

namespace nesshi::assembler {

void fill_data(Layout& layout, Diagnostics& diags) {
    for (DataSec& s : layout.data)
        if (s.size <= kMaxSection && s.address + s.size <= (uint64_t{1} << 32)) s.bytes.assign(size_t(s.size), 0);
    Resolver resolve = layout.resolver();
    for (const DataFill& f : layout.fills) {
        const DirectiveRec& d = *f.dir;
        DataSec& s = layout.data[f.section];
        int width = d.name == ".half" ? 2 : d.name == ".byte" ? 1 : 4;
        int64_t lo = width == 4 ? INT32_MIN : width == 2 ? INT16_MIN : INT8_MIN;
        int64_t hi = width == 4 ? int64_t(UINT32_MAX) : width == 2 ? UINT16_MAX : UINT8_MAX;
        for (size_t i = 0; i < d.args.size(); ++i) {
            Loc loc = i < d.arg_locs.size() ? d.arg_locs[i] : d.loc;
            uint64_t value = 0;
            std::string err;
            if (d.name == ".float") {
                if (auto bits = float_literal(d.args[i], err)) value = *bits;
                else if (!err.empty()) {
                    diags.error(loc, err);
                    continue;
                }
            }
            if (d.name != ".float" || (err.empty() && !float_literal(d.args[i], err))) {
                ExprResult r = eval_expr(d.args[i], resolve);
                if (!r.ok) {
                    diags.error(Loc{loc.file, loc.line, r.col}, r.error);
                    continue;
                }
                if (r.value < lo || r.value > hi) {
                    diags.error(loc, fmt::format("value {} does not fit in {} bits", r.value, width * 8));
                    continue;
                }
                value = uint64_t(r.value);
            }
            size_t at = size_t(f.offset) + i * size_t(width);
            for (int b = 0; b < width && at + size_t(b) < s.bytes.size(); ++b)
                s.bytes[at + size_t(b)] = uint8_t(value >> (8 * b));
        }
    }
}

void check_data_regions(const Layout& layout, const isa::Machine& m, Diagnostics& diags) {
    for (const DataSec& s : layout.data) {
        if (s.bytes.empty() || m.memory_at(s.address, uint32_t(s.bytes.size()))) continue;
        const uint64_t last = uint64_t{s.address} + s.bytes.size() - 1;
        Diagnostic& d = diags.error(s.loc, fmt::format("data at 0x{:08x}..0x{:08x} ({} bytes) does not fit in a memory "
                                                       "region of machine '{}'", s.address, last, s.bytes.size(), m.name));
        for (const isa::MemoryDesc& r : m.memories)
            Diagnostics::note(d, Loc{s.loc.file, 0, 0}, fmt::format("region {}: 0x{:08x}..0x{:08x}", r.name, r.base,
                                                                    uint64_t{r.base} + r.size - 1));
    }
}

void apply_globals(Layout& layout, Diagnostics& diags) {
    for (const DirectiveRec* d : layout.globals)
        for (size_t i = 0; i < d->args.size(); ++i) {
            Loc loc = i < d->arg_locs.size() ? d->arg_locs[i] : d->loc;
            const auto& a = d->args[i];
            if (a.size() != 1 || a[0].kind != Tok::Ident) {
                diags.error(loc, ".global expects label names");
                continue;
            }
            auto it = layout.symbols.find(a[0].text);
            if (it == layout.symbols.end()) {
                diags.error(loc, fmt::format(".global names undefined label '{}'", a[0].text));
                continue;
            }
            if (it->second.kind == SymbolDef::Kind::Equ) {
                diags.error(loc, fmt::format("'{}' is an .equ constant, not a label", a[0].text));
                continue;
            }
            it->second.global = true;
        }
}

isa::ObjectFile build_object(const Layout& layout, const isa::Machine& m) {
    isa::ObjectFile obj;
    obj.machine = m.name;
    obj.machine_fingerprint = m.fingerprint();
    for (const PlacedBundle& b : layout.bundles) {
        std::vector<isa::Instr> ops;
        for (const auto& o : b.rec->ops) ops.push_back(o.instr);
        std::stable_sort(ops.begin(), ops.end(), [](const isa::Instr& a, const isa::Instr& c) { return a.slot < c.slot; });
        for (size_t i = 0; i < ops.size(); ++i) obj.code.push_back(isa::encode(ops[i], i + 1 == ops.size()));
        auto f = std::find(obj.files.begin(), obj.files.end(), b.file);
        if (f == obj.files.end()) {
            obj.files.push_back(b.file);
            f = obj.files.end() - 1;
        }
        obj.lines.push_back({uint32_t(f - obj.files.begin()), b.line});
    }
    for (const DataSec& s : layout.data)
        if (!s.bytes.empty()) obj.data.push_back({s.address, s.bytes});
    for (const auto& [name, s] : layout.symbols) {
        if (s.kind == SymbolDef::Kind::Equ) continue;
        obj.symbols.push_back({name, s.kind == SymbolDef::Kind::Code ? isa::SymbolKind::Code : isa::SymbolKind::Data,
                               uint32_t(s.value), s.global});
    }
    std::sort(obj.symbols.begin(), obj.symbols.end(), [](const isa::Symbol& a, const isa::Symbol& b) {
        return std::tie(a.kind, a.value, a.name) < std::tie(b.kind, b.value, b.name);
    });
    return obj;
}

} // namespace nesshi::assembler
