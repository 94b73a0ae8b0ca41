// The printer for operations (see printer.hpp).
#include "isa/printer.hpp"

#include <bit>
#include <cmath>

namespace nesshi::isa {

std::string format_float_bits(uint32_t bits) {
    float x = std::bit_cast<float>(bits);
    if (!std::isfinite(x)) return fmt::format("0x{:08x}", bits);
    std::string s = fmt::format("{}", x);
    // Keep a float look so a reader never mistakes it for an integer.
    if (s.find_first_of(".eE") == std::string::npos) s += ".0";
    return s;
}

std::string format_operands(const Instr& in, const TargetNamer& namer) {
    const OpInfo& info = in.info();
    std::string out;
    for (int i = 0; i < info.num_operands; ++i) {
        const Operand& o = info.operands[i];
        if (i) out += ", ";
        switch (o.kind) {
        case OperandKind::IntReg: out += fmt::format("r{}", field_value(in, o.field)); break;
        case OperandKind::FloatReg: out += fmt::format("f{}", field_value(in, o.field)); break;
        case OperandKind::Imm: out += fmt::format("{}", static_cast<int32_t>(in.imm)); break;
        case OperandKind::FloatImm: out += format_float_bits(in.imm); break;
        case OperandKind::Mem:
            out += fmt::format("{}(r{})", static_cast<int32_t>(in.imm), in.rs1);
            break;
        case OperandKind::Target: {
            std::string name = namer ? namer(in.imm) : std::string();
            out += name.empty() ? fmt::format("{}", in.imm) : name;
            break;
        }
        case OperandKind::Channel: out += fmt::format("{}", in.imm); break;
        }
    }
    return out;
}

std::string format_instr(const Instr& in, const TargetNamer& namer) {
    const OpInfo& info = in.info();
    if (info.num_operands == 0) return std::string(info.mnemonic);
    return fmt::format("{} {}", info.mnemonic, format_operands(in, namer));
}

std::string format_instr_slotted(const Instr& in, const Machine& m, const TargetNamer& namer) {
    std::string slot = in.slot < m.slots.size() ? m.slots[in.slot].name : fmt::format("slot{}", in.slot);
    return fmt::format("{}: {}", slot, format_instr(in, namer));
}

} // namespace nesshi::isa
