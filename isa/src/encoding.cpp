// Encoder and decoder for the 64-bit operation word (layout in encoding.hpp).
#include "isa/encoding.hpp"

#include <fmt/core.h>

namespace nesshi::isa {

namespace {
constexpr int kOpShift = 56, kSlotShift = 53, kRdShift = 46, kRs1Shift = 39, kRs2Shift = 32;
constexpr uint64_t k7 = 0x7f, k3 = 0x7;
constexpr unsigned bit(Field f) { return 1u << static_cast<int>(f); }
} // namespace

unsigned used_fields(const OpInfo& info) {
    unsigned used = 0;
    for (int i = 0; i < info.num_operands; ++i) {
        used |= bit(info.operands[i].field);
        if (info.operands[i].kind == OperandKind::Mem) used |= bit(Field::Rs1);
    }
    return used;
}

uint8_t field_value(const Instr& in, Field f) {
    switch (f) {
    case Field::Rd: return in.rd;
    case Field::Rs1: return in.rs1;
    case Field::Rs2: return in.rs2;
    case Field::Rs3: return in.rs3;
    case Field::Imm: return 0;
    }
    return 0;
}

RegOperands register_operands(const Instr& in) {
    RegOperands out;
    const OpInfo& info = in.info();
    for (int i = 0; i < info.num_operands; ++i) {
        const Operand& o = info.operands[i];
        if (o.kind == OperandKind::IntReg)
            out.items[out.count++] = {RegFile::Int, field_value(in, o.field), o.is_dest};
        else if (o.kind == OperandKind::FloatReg)
            out.items[out.count++] = {RegFile::Float, field_value(in, o.field), o.is_dest};
        else if (o.kind == OperandKind::Mem)
            out.items[out.count++] = {RegFile::Int, in.rs1, false, true};
    }
    return out;
}

uint64_t encode(const Instr& in, bool end_of_bundle) {
    uint64_t w = end_of_bundle ? kEndOfBundle : 0;
    w |= (uint64_t{in.opcode} & k7) << kOpShift;
    w |= (uint64_t{in.slot} & k3) << kSlotShift;
    w |= (uint64_t{in.rd} & k7) << kRdShift;
    w |= (uint64_t{in.rs1} & k7) << kRs1Shift;
    w |= (uint64_t{in.rs2} & k7) << kRs2Shift;
    w |= (used_fields(in.info()) & bit(Field::Rs3)) ? (uint64_t{in.rs3} & k7) : uint64_t{in.imm};
    return w;
}

DecodeResult decode(uint64_t w) {
    DecodeResult r;
    r.end_of_bundle = (w & kEndOfBundle) != 0;
    unsigned opc = unsigned((w >> kOpShift) & k7);
    if (opc >= unsigned(kNumOps)) {
        r.error = fmt::format("unknown opcode {}", opc);
        return r;
    }
    Instr& in = r.instr;
    in.opcode = Opcode(opc);
    in.slot = uint8_t((w >> kSlotShift) & k3);
    in.rd = uint8_t((w >> kRdShift) & k7);
    in.rs1 = uint8_t((w >> kRs1Shift) & k7);
    in.rs2 = uint8_t((w >> kRs2Shift) & k7);
    uint32_t low = uint32_t(w);
    unsigned used = used_fields(in.info());
    if (used & bit(Field::Rs3)) {
        if (low > k7) {
            r.error = fmt::format("{}: nonzero bits above rs3", in.info().mnemonic);
            return r;
        }
        in.rs3 = uint8_t(low);
    } else {
        in.imm = low;
    }
    auto reject_unused = [&](Field f, uint32_t v, const char* name) {
        if (!(used & bit(f)) && v != 0 && r.error.empty())
            r.error = fmt::format("{}: unused field {} is not zero", in.info().mnemonic, name);
    };
    reject_unused(Field::Rd, in.rd, "rd");
    reject_unused(Field::Rs1, in.rs1, "rs1");
    reject_unused(Field::Rs2, in.rs2, "rs2");
    if (!(used & (bit(Field::Imm) | bit(Field::Rs3)))) reject_unused(Field::Imm, low, "imm");
    r.ok = r.error.empty();
    return r;
}

} // namespace nesshi::isa
