// The 64-bit operation word: encoder, decoder, and the decoded form every tool shares.
//
//   63     end of bundle (1 on the last operation of a bundle)
//   62..56 opcode (index into kOps)
//   55..53 issue slot (index into the machine's slot list)
//   52..46 rd     45..39 rs1     38..32 rs2
//   31..0  imm (immediate, memory offset, branch target, channel); rs3 in imm[6:0]
// Fields an operation does not use must be zero; the decoder rejects anything else, so every
// word either decodes to exactly one operation or is reported as an illegal encoding.
#pragma once

#include "isa/ops.hpp"

#include <array>
#include <cstdint>
#include <string>

namespace nesshi::isa {

struct Instr {
    Opcode opcode = 0;
    uint8_t slot = 0;
    uint8_t rd = 0, rs1 = 0, rs2 = 0, rs3 = 0;
    uint32_t imm = 0;

    const OpInfo& info() const { return kOps[opcode]; }
    friend bool operator==(const Instr&, const Instr&) = default;
};

inline constexpr uint64_t kEndOfBundle = uint64_t{1} << 63;
inline constexpr int kMaxSlots = 8;
inline constexpr int kMaxRegs = 128;

uint64_t encode(const Instr& in, bool end_of_bundle);

// The register number held in a register field (0 for Field::Imm).
uint8_t field_value(const Instr& in, Field f);

// One register an operation reads or writes.
struct RegOperand {
    RegFile file;
    uint8_t reg;
    bool write;
    bool base = false; // a memory operand's base register (a read)
};

// Every register an operation reads or writes, in operand order; a memory operand's base
// register is a read. The one walk over operands that port checks, hazards and tools share.
struct RegOperands {
    std::array<RegOperand, 4> items{};
    uint8_t count = 0;
    const RegOperand* begin() const { return items.data(); }
    const RegOperand* end() const { return items.data() + count; }
};
RegOperands register_operands(const Instr& in);

struct DecodeResult {
    bool ok = false;
    Instr instr;
    bool end_of_bundle = false;
    std::string error; // why the word is illegal
};
DecodeResult decode(uint64_t word);

// Which fields an operation uses (bit i set = Field(i) used).
unsigned used_fields(const OpInfo& info);

} // namespace nesshi::isa
