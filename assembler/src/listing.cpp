// Listing text (see listing.hpp). Columns of a bundle line:
//   ADDR  ENCODING          SLOT  SOURCE
// followed by `      ports IRF rR/P wW/P  FPRF ...   units U/S (names)`.
#include "listing.hpp"

#include "isa/bundle_check.hpp"

#include <fmt/format.h>

#include <map>

namespace nesshi::assembler {

std::string make_listing(const Layout& layout, const isa::ObjectFile& obj, const isa::Machine& m) {
    std::string out = fmt::format("# listing for machine {} ({} bundles, {} operations)\n"
                                  "# addr  encoding            slot   source\n",
                                  m.name, layout.bundles.size(), obj.code.size());
    std::multimap<uint32_t, std::string> code_labels, data_labels;
    for (const auto& s : obj.symbols)
        (s.kind == isa::SymbolKind::Code ? code_labels : data_labels).emplace(s.value, s.name);
    size_t word = 0;
    for (size_t b = 0; b < layout.bundles.size(); ++b) {
        auto range = code_labels.equal_range(uint32_t(b));
        for (auto it = range.first; it != range.second; ++it) out += fmt::format("{}:\n", it->second);
        std::vector<const OpRec*> ops;
        for (const auto& o : layout.bundles[b].rec->ops) ops.push_back(&o);
        std::stable_sort(ops.begin(), ops.end(), [](const OpRec* a, const OpRec* c) { return a->instr.slot < c->instr.slot; });
        std::vector<isa::Instr> instrs;
        for (size_t i = 0; i < ops.size(); ++i) {
            const OpRec& o = *ops[i];
            instrs.push_back(o.instr);
            std::string slot = o.instr.slot < m.slots.size() ? m.slots[o.instr.slot].name : "?";
            out += fmt::format("{:>6}  {:016x}    {:<6} {}\n", i == 0 ? fmt::format("{:04}", b) : "",
                               word < obj.code.size() ? obj.code[word] : 0, slot, o.text);
            ++word;
        }
        isa::BundleUsage u = isa::bundle_usage(instrs);
        std::string ports;
        for (int f = 0; f < isa::kNumRegFiles; ++f)
            ports += fmt::format("{}{} r{}/{} w{}/{}", f ? "  " : "", isa::kRegFileNames[size_t(f)], u.reads[size_t(f)],
                                 m.regs[size_t(f)].read_ports, u.writes[size_t(f)], m.regs[size_t(f)].write_ports);
        std::string units;
        for (const auto& in : instrs) units += (units.empty() ? "" : " ") + m.slots[in.slot].name;
        out += fmt::format("        ports {}   units {}/{} ({})\n", ports, instrs.size(), m.slots.size(), units);
    }
    for (auto it = code_labels.lower_bound(uint32_t(layout.bundles.size())); it != code_labels.end(); ++it)
        out += fmt::format("{}:\n", it->second);
    for (const auto& d : obj.data) {
        out += fmt::format("# data at 0x{:08x}, {} bytes\n", d.address, d.bytes.size());
        // Rows of up to 16 bytes; a label starts a new row.
        size_t i = 0;
        while (i < d.bytes.size()) {
            uint32_t addr = d.address + uint32_t(i);
            auto range = data_labels.equal_range(addr);
            for (auto it = range.first; it != range.second; ++it) out += fmt::format("{}:\n", it->second);
            std::string hex;
            size_t j = i;
            do hex += fmt::format(" {:02x}", d.bytes[j++]);
            while (j < d.bytes.size() && j - i < 16 && !data_labels.count(d.address + uint32_t(j)));
            out += fmt::format("{:08x} {}\n", addr, hex);
            i = j;
        }
    }
    return out;
}

} // namespace nesshi::assembler
