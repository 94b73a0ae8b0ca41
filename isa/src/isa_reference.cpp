// Renders docs/isa.md from kOps and the built-in machine presets; a test keeps the file current.
#include "isa/reference.hpp"

#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>

namespace nesshi::isa {

namespace {
// A source register is named after the field it is encoded in (rs1, rs2, rs3), as the row's
// summary names it: a store's value is rs2 beside its base rs1, whatever their order in the text.
int source_number(Field f) { return f == Field::Rs1 ? 1 : f == Field::Rs2 ? 2 : 3; }

std::string operand_syntax(const OpInfo& op) {
    std::string s;
    for (int i = 0; i < op.num_operands; ++i) {
        const Operand& o = op.operands[i];
        if (i) s += ", ";
        switch (o.kind) {
        case OperandKind::IntReg:
            s += o.is_dest ? "rd" : fmt::format("rs{}", source_number(o.field));
            break;
        case OperandKind::FloatReg:
            s += o.is_dest ? "fd" : fmt::format("fs{}", source_number(o.field));
            break;
        case OperandKind::Imm: s += "imm"; break;
        case OperandKind::FloatImm: s += "fimm"; break;
        case OperandKind::Mem: s += "imm(rs1)"; break;
        case OperandKind::Target: s += "target"; break;
        case OperandKind::Channel: s += "ch"; break;
        }
    }
    return s;
}

// A '|' in a table cell (`or`: rd = rs1 | rs2) would end the cell; Markdown takes it escaped.
std::string table_cell(std::string_view text) {
    std::string s;
    for (char c : text) {
        if (c == '|') s += '\\';
        s += c;
    }
    return s;
}

std::string ports(const OpInfo& op) {
    PortUse p = port_use(op);
    std::string s;
    for (int f = 0; f < kNumRegFiles; ++f) {
        if (p.reads[f]) s += fmt::format("{}{} r{}", s.empty() ? "" : " ", kRegFileNames[f], p.reads[f]);
        if (p.writes[f]) s += fmt::format("{}{} w{}", s.empty() ? "" : " ", kRegFileNames[f], p.writes[f]);
    }
    return s.empty() ? "-" : s;
}
// The description file format and the inheritance rules (isa/src/machine.cpp implements them).
std::string machine_files_section() {
    std::string out = "\n## Machine description files\n\n";
    out += "A machine is a TOML file, given wherever a preset name is accepted (`-m FILE`); "
           "the presets below are such files (`isa/machines/*.toml`, printed by "
           "`nesshi isa --machine-toml NAME`). Keys:\n\n"
           "| key | meaning |\n|---|---|\n"
           "| `name` | the machine's name (required; objects record it) |\n"
           "| `description` | one line for listings |\n"
           "| `inherits` | a parent description (below) |\n"
           "| `branch_penalty` | bubble cycles after a taken branch (default 0) |\n";
    out += fmt::format("| `[registers.int]`, `[registers.float]` | `count` (1..{}), `read_ports` "
                       "and `write_ports` (1..64) of the IRF and the FPRF |\n",
                       kMaxRegs);
    out += fmt::format("| `[latency]` | cycles from issue until the result lands, at least 1, for "
                       "each operation class: {} |\n",
                       fmt::join(kOpClassNames.begin(), kOpClassNames.end(), ", "));
    out += fmt::format("| `[[slot]]` | one issue slot each (at most {}): `name`, and `accepts`, "
                       "the classes it issues; every class needs a slot |\n",
                       kMaxSlots);
    out += "| `[[memory]]` | one region each: `name`, `base` and `size` (multiples of 4, no "
           "overlaps), `latency` (extra stall cycles per access, default 0), `cached` (default "
           "false) |\n\n"
           "Errors name the file, line and column (`file:line:col: error: ...`); unknown keys "
           "are errors.\n\n";
    out += "### Inheritance\n\n"
           "`inherits = \"NAME\"` starts the description as a copy of the machine NAME, and the "
           "file lists only its differences. NAME is a preset, else a file path relative to the "
           "directory of the inheriting file (a preset may inherit only presets). The parent is "
           "a complete description (it may inherit in turn) and is checked on its own first. The "
           "rules:\n\n"
           "- `name` must be given by the child; `description` is never inherited (a child "
           "without one has none).\n"
           "- `branch_penalty` is the child's if given, else the parent's.\n"
           "- `[registers.int]`, `[registers.float]` and `[latency]` override key by key: a key "
           "the child gives replaces the parent's, the others stay the parent's.\n"
           "- `[[slot]]` and `[[memory]]`: a child that gives any entry of the array replaces the "
           "parent's whole array (to add a slot, list them all); without entries the child keeps "
           "the parent's.\n"
           "- What the child gives is checked as in a complete file (ranges, every class "
           "issuable, memories not overlapping).\n";
    out += fmt::format("- Errors: an unknown parent, a cycle (a description that reaches itself), "
                       "or a chain of more than {} ancestors, each at the `inherits` line.\n\n"
                       "The `-real` presets are written this way: each inherits its ideal "
                       "preset and lists its latencies and branch penalty.\n\n",
                       kMaxInheritDepth);
    return out;
}
} // namespace

std::string isa_reference_markdown() {
    std::string out;
    out += "# Nesshisen ISA reference\n\n";
    out += "Generated from `isa/include/isa/ops.hpp` and `isa/machines/*.toml` by "
           "`nesshi isa --markdown`; a test keeps this file up to date. Do not edit by hand.\n\n";
    out += "## Conventions\n\n"
           "- 32-bit integers (two's complement, wrapping) and IEEE-754 binary32 floats, round to "
           "nearest even; subnormals are kept (not flushed); no fused multiply-add.\n"
           "- Registers `r0..r127` (IRF) and `f0..f127` (FPRF); no register is hard-wired to "
           "zero. Conditions live in integer registers: compares write 0 or 1.\n"
           "- Every register read counts against its file's read ports at issue; every write "
           "counts against the write ports in the cycle it lands (issue + latency).\n"
           "- Exposed pipeline: a result can be read by a bundle issued `latency` cycles after "
           "its producer, not earlier; there are no interlocks. All units are pipelined.\n"
           "- A register may not be read while a newer write to it is in flight: a reader of the "
           "old value issues no later than the producer that overwrites it (the same bundle is "
           "allowed, as a bundle reads its sources at issue), so the value a read sees never "
           "depends on timing. The assembler reports every such read and the checked ISS stops "
           "at one.\n"
           "- Writes to one register land in issue order: a write may not land before, or in the "
           "same cycle as, an earlier-issued write to that register still in flight (in one bundle, "
           "a lower slot issues first), so the value left never depends on latencies. The assembler "
           "reports every such write and the checked ISS stops at one (`write-order`, `dup-write`). "
           "Stalls (memory latency, a cache, FIFO waits) only delay later bundles, so they cannot "
           "reorder writes the assembler accepts.\n"
           "- A taken branch redirects the next bundle (plus the machine's `branch_penalty` "
           "bubble cycles). Branch targets are absolute bundle addresses.\n"
           "- Memory is byte-addressed; accesses must be aligned to their width.\n"
           "- `fadd`, `fsub`, `fmul`, `fdiv` and `fsqrt` return the canonical quiet NaN 0x7fc00000 "
           "whenever the result is NaN (the host's NaN payload depends on operand order); `fmin`/`fmax` "
           "return the second operand when either is NaN; `ftoi` truncates, saturates and maps NaN to 0.\n\n";
    out += "## Encoding\n\nEach operation is a 64-bit word; a bundle is a run of words whose "
           "last has bit 63 set.\n\n"
           "| bits | field |\n|---|---|\n| 63 | end of bundle |\n| 62..56 | opcode |\n"
           "| 55..53 | issue slot |\n| 52..46 | rd |\n| 45..39 | rs1 |\n| 38..32 | rs2 |\n"
           "| 31..0 | imm / offset / target / channel; rs3 in bits 6..0 |\n\n"
           "Unused fields must be zero; any other word is an illegal encoding.\n\n";
    out += "## Operations\n\n| opcode | mnemonic | operands | class | ports | meaning |\n"
           "|---:|---|---|---|---|---|\n";
    for (int i = 0; i < kNumOps; ++i) {
        const OpInfo& op = kOps[i];
        out += fmt::format("| {} | `{}` | `{}` | {} | {} | {} |\n", i, op.mnemonic,
                           operand_syntax(op), kOpClassNames[int(op.cls)], ports(op),
                           table_cell(op.summary));
    }
    out += machine_files_section();
    out += "## Machine presets\n\n";
    for (auto name : preset_names()) {
        Machine m = load_machine(name);
        out += fmt::format("### `{}`\n\n{}\n\n", m.name, m.description);
        out += "| slot | accepts |\n|---|---|\n";
        for (const auto& s : m.slots) {
            std::vector<std::string_view> cls;
            for (int c = 0; c < kNumOpClasses; ++c)
                if (s.accepts(OpClass(c))) cls.push_back(kOpClassNames[c]);
            out += fmt::format("| {} | {} |\n", s.name, fmt::join(cls, ", "));
        }
        out += "\n| register file | count | read ports | write ports |\n|---|---:|---:|---:|\n";
        for (int f = 0; f < kNumRegFiles; ++f)
            out += fmt::format("| {} | {} | {} | {} |\n", kRegFileNames[f], m.regs[f].count,
                               m.regs[f].read_ports, m.regs[f].write_ports);
        out += "\n| class | latency |\n|---|---:|\n";
        for (int c = 0; c < kNumOpClasses; ++c)
            out += fmt::format("| {} | {} |\n", kOpClassNames[c], m.latency[c]);
        out += fmt::format("\nTaken-branch penalty: {} cycles.\n\n", m.branch_penalty);
        out += "| memory | base | size | extra latency | cached |\n|---|---|---|---:|---|\n";
        for (const auto& d : m.memories)
            out += fmt::format("| {} | 0x{:08x} | {} KiB | {} | {} |\n", d.name, d.base,
                               d.size / 1024, d.latency, d.cached ? "yes" : "no");
        out += "\n";
    }
    return out;
}

} // namespace nesshi::isa
