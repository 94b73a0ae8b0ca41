// Text form of operations: the one printer used by the disassembler, listings, traces,
// fault reports and the debugger. Its output is what the assembler parses.
#pragma once

#include "isa/encoding.hpp"
#include "isa/machine.hpp"

#include <fmt/format.h>

#include <functional>
#include <string>

namespace nesshi::isa {

// Names a branch target (a bundle address); return empty to print the number.
using TargetNamer = std::function<std::string(uint32_t)>;

std::string format_operands(const Instr& in, const TargetNamer& namer = {});
// "fadd f1, f2, f3"
std::string format_instr(const Instr& in, const TargetNamer& namer = {});
// "fpu0: fadd f1, f2, f3" (slot name from the machine; the number if out of range)
std::string format_instr_slotted(const Instr& in, const Machine& m, const TargetNamer& namer = {});
// A float immediate as the assembler reads it back bit-exactly (hex bits when not finite).
std::string format_float_bits(uint32_t bits);

} // namespace nesshi::isa

template <> struct fmt::formatter<nesshi::isa::Instr> : fmt::formatter<std::string> {
    auto format(const nesshi::isa::Instr& in, format_context& ctx) const {
        return fmt::formatter<std::string>::format(nesshi::isa::format_instr(in), ctx);
    }
};
