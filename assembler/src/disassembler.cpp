// The disassembler: assembly text that re-assembles to a byte-identical object.
//
// Every operation carries its slot prefix (so slot assignment is reproduced), bundles of more
// than one op are braced, labels come from the symbol table, `.file`/`.loc` reproduce the line
// table, and each data section is printed at its address with .word/.byte.
#include "assembler/assembler.hpp"

#include "isa/bundle_check.hpp"
#include "isa/printer.hpp"
#include "lexer.hpp"

#include <fmt/format.h>

#include <map>
#include <set>

namespace nesshi::assembler {

namespace {

void print_data(std::string& out, const isa::DataSection& d, const std::multimap<uint32_t, std::string>& labels,
                bool include_end) {
    out += fmt::format("\n.data 0x{:08x}\n", d.address);
    size_t n = d.bytes.size();
    auto labels_at = [&](uint64_t addr) {
        auto r = labels.equal_range(uint32_t(addr));
        for (auto it = r.first; it != r.second; ++it) out += fmt::format("{}:\n", it->second);
    };
    auto label_inside = [&](uint64_t from, uint64_t to) { // any label in (from, to)
        auto it = labels.upper_bound(uint32_t(from));
        return it != labels.end() && it->first < to;
    };
    size_t i = 0;
    while (i < n) {
        uint64_t addr = uint64_t(d.address) + i;
        labels_at(addr);
        std::vector<std::string> items;
        bool words = addr % 4 == 0 && i + 4 <= n && !label_inside(addr, addr + 4);
        size_t width = words ? 4 : 1;
        while (i < n && items.size() < (words ? 4u : 8u)) {
            uint64_t a = uint64_t(d.address) + i;
            if (!items.empty() && labels.count(uint32_t(a))) break;
            if (words && (i + 4 > n || label_inside(a, a + 4))) break;
            if (!words && a % 4 == 0 && i + 4 <= n && !items.empty()) break;
            uint32_t v = 0;
            for (size_t b = 0; b < width; ++b) v |= uint32_t(d.bytes[i + b]) << (8 * b);
            items.push_back(words ? fmt::format("0x{:08x}", v) : fmt::format("0x{:02x}", v));
            i += width;
        }
        out += fmt::format("    {} {}\n", words ? ".word" : ".byte", fmt::join(items, ", "));
    }
    if (include_end) labels_at(uint64_t(d.address) + n);
}

} // namespace

std::string disassemble(const isa::ObjectFile& obj, const isa::Machine& m, const DisOptions& opts) {
    if (obj.machine_fingerprint != m.fingerprint()) {
        if (obj.machine != m.name)
            throw isa::ObjectError(fmt::format("object was assembled for machine '{}', not '{}'", obj.machine, m.name));
        throw isa::ObjectError(fmt::format("object was assembled for a different description of machine '{}' "
                                           "(fingerprint {:016x}; this one has {:016x})",
                                           obj.machine, obj.machine_fingerprint, m.fingerprint()));
    }
    auto bundles = isa::decode_bundles(obj);
    for (size_t b = 0; b < bundles.size(); ++b) {
        auto v = isa::check_bundle(m, bundles[b]);
        if (!v.empty())
            throw isa::ObjectError(fmt::format("bundle {} is not valid on {}: {}", b, m.name, v.front().message));
        for (const isa::Instr& in : bundles[b]) // as the assembler requires: a target names a bundle
            for (int k = 0; k < in.info().num_operands; ++k)
                if (in.info().operands[size_t(k)].kind == isa::OperandKind::Target && in.imm >= bundles.size())
                    throw isa::ObjectError(fmt::format("bundle {}: branch target {} is outside the code (bundles 0..{})",
                                                       b, in.imm, int64_t(bundles.size()) - 1));
    }
    std::set<std::string_view> names;
    for (const auto& s : obj.symbols) {
        if (!is_identifier(s.name))
            throw isa::ObjectError(fmt::format("symbol at {} {} has a name that is not an identifier",
                                               s.kind == isa::SymbolKind::Code ? "bundle" : "address", s.value));
        if (is_register_name(s.name) || m.slot_index(s.name) >= 0) // the parser's rule for a label
            throw isa::ObjectError(fmt::format("symbol '{}' has the name of a register or issue slot", s.name));
        if (!names.insert(s.name).second) throw isa::ObjectError(fmt::format("symbol '{}' is defined twice", s.name));
    }
    std::multimap<uint32_t, std::string> code_labels, data_labels;
    std::map<uint32_t, std::string> target_names;
    std::string out = fmt::format("# disassembly of an object for machine {}\n", obj.machine);
    for (const auto& s : obj.symbols) {
        (s.kind == isa::SymbolKind::Code ? code_labels : data_labels).emplace(s.value, s.name);
        if (s.kind == isa::SymbolKind::Code) target_names.try_emplace(s.value, s.name);
    }
    for (const auto& s : obj.symbols)
        if (s.global) out += fmt::format(".global {}\n", s.name);
    isa::TargetNamer namer = [&](uint32_t t) {
        auto it = target_names.find(t);
        return it == target_names.end() ? std::string() : it->second;
    };
    out += ".text\n";
    bool lines = opts.lines && obj.lines.size() == bundles.size();
    uint32_t file = UINT32_MAX;
    for (size_t b = 0; b < bundles.size(); ++b) {
        if (lines) {
            const isa::LineEntry& l = obj.lines[b];
            if (l.file != file && l.file < obj.files.size()) {
                file = l.file;
                out += fmt::format(".file {}\n", quote(obj.files[file]));
            }
            out += fmt::format(".loc {}\n", l.line);
        }
        auto r = code_labels.equal_range(uint32_t(b));
        for (auto it = r.first; it != r.second; ++it) out += fmt::format("{}:\n", it->second);
        auto text = [&](const isa::Instr& in) {
            return opts.slots ? isa::format_instr_slotted(in, m, namer) : isa::format_instr(in, namer);
        };
        if (bundles[b].size() == 1) {
            out += fmt::format("    {}\n", text(bundles[b][0]));
            continue;
        }
        out += "    {\n";
        for (const auto& in : bundles[b]) out += fmt::format("        {}\n", text(in));
        out += "    }\n";
    }
    for (auto it = code_labels.lower_bound(uint32_t(bundles.size())); it != code_labels.end(); ++it)
        out += fmt::format("{}:\n", it->second);
    // Each data label goes into the first section that contains it (or ends at it).
    std::vector<std::multimap<uint32_t, std::string>> per(obj.data.size());
    std::multimap<uint32_t, std::string> orphans;
    for (const auto& [addr, name] : data_labels) {
        bool placed = false;
        for (size_t i = 0; i < obj.data.size() && !placed; ++i) {
            const auto& d = obj.data[i];
            if (addr >= d.address && uint64_t(addr) <= uint64_t(d.address) + d.bytes.size()) {
                per[i].emplace(addr, name);
                placed = true;
            }
        }
        if (!placed) orphans.emplace(addr, name);
    }
    for (size_t i = 0; i < obj.data.size(); ++i) print_data(out, obj.data[i], per[i], true);
    for (const auto& [addr, name] : orphans) out += fmt::format("\n.data 0x{:08x}\n{}:\n", addr, name);
    return out;
}

} // namespace nesshi::assembler
