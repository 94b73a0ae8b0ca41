// The instruction set, defined once: one constexpr row per operation.
//
// Everything else derives from `kOps`: the encoder and decoder (encoding.hpp), the printer and
// the assembler's operand matcher, register-port accounting, the ISS's semantics dispatch and
// the generated reference docs/isa.md. Adding an operation is one row here, nothing else.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <type_traits>

namespace nesshi::isa {

// Unit/latency class of an operation. A machine description says which classes each issue
// slot accepts and the latency of each class.
enum class OpClass : uint8_t { Alu, Mul, FAdd, FMul, FDiv, Load, Store, Branch, Fifo, Misc };
inline constexpr int kNumOpClasses = 10;
inline constexpr std::array<std::string_view, kNumOpClasses> kOpClassNames = {
    "alu", "mul", "fadd", "fmul", "fdiv", "load", "store", "branch", "fifo", "misc"};

// What the simulator does with the row's `eval` result.
enum class Kind : uint8_t {
    Compute, // rd = eval(a, b, c, imm)
    Load,    // rd = mem[eval(...)]      (eval gives the address)
    Store,   // mem[eval(...)] = b       (eval gives the address; b is the data register)
    Branch,  // if eval(...) != 0: pc = imm
    Jump,    // pc = imm
    JumpLink,// rd = pc + 1; pc = imm
    JumpReg, // pc = a
    Recv,    // rd = fifo[imm].pop()  (blocks while empty)
    Send,    // fifo[imm].push(a)
    Halt,
    Nop,
};

enum class RegFile : uint8_t { Int, Float };
inline constexpr int kNumRegFiles = 2;
inline constexpr std::array<std::string_view, kNumRegFiles> kRegFileNames = {"IRF", "FPRF"};

// Encoding fields of a 64-bit operation word (see encoding.hpp for bit positions).
enum class Field : uint8_t { Rd, Rs1, Rs2, Rs3, Imm };

// Syntax of one operand. `Mem` is `imm(rs1)`: base register in Rs1, offset in Imm.
enum class OperandKind : uint8_t { IntReg, FloatReg, Imm, FloatImm, Mem, Target, Channel };

struct Operand {
    OperandKind kind;
    Field field;
    bool is_dest = false;
};

// Semantics: a pure function of the source values (raw 32-bit patterns) and the immediate.
using Eval = uint32_t (*)(uint32_t a, uint32_t b, uint32_t c, uint32_t imm);

struct OpInfo {
    std::string_view mnemonic;
    OpClass cls;
    Kind kind;
    std::array<Operand, 4> operands;
    uint8_t num_operands;
    Eval eval;
    uint8_t mem_bytes = 0;    // loads and stores: access width
    bool mem_signed = false;  // loads: sign-extend
    std::string_view summary; // one line for docs/isa.md
};

namespace detail {
constexpr float f(uint32_t x) { return std::bit_cast<float>(x); }
constexpr uint32_t u(float x) { return std::bit_cast<uint32_t>(x); }
constexpr int32_t s(uint32_t x) { return static_cast<int32_t>(x); }
// An arithmetic result: any NaN becomes the canonical quiet NaN. The host's NaN payload depends
// on operand order, which the compiler may change, so the ISA defines it (as RISC-V does).
inline constexpr uint32_t kCanonicalNaN = 0x7fc00000u;
// A branch the compiler keeps (the empty asm stops it turning it into a select): NaNs are rare,
// and a select moved every arithmetic result through an integer register and a cmov on its way
// to the next operation.
constexpr uint32_t q(float x) {
    if (x != x) [[unlikely]] {
        if (!std::is_constant_evaluated()) asm volatile("");
        return kCanonicalNaN;
    }
    return std::bit_cast<uint32_t>(x);
}

// float -> int32: truncate toward zero, saturate out-of-range values, NaN gives 0.
inline uint32_t ftoi(uint32_t a) {
    float x = f(a);
    if (std::isnan(x)) return 0;
    if (x >= 2147483648.0f) return 0x7fffffffu;
    if (x < -2147483648.0f) return 0x80000000u;
    return static_cast<uint32_t>(static_cast<int32_t>(x));
}

constexpr Operand RD{OperandKind::IntReg, Field::Rd, true};
constexpr Operand FD{OperandKind::FloatReg, Field::Rd, true};
constexpr Operand RS1{OperandKind::IntReg, Field::Rs1};
constexpr Operand RS2{OperandKind::IntReg, Field::Rs2};
constexpr Operand RS3{OperandKind::IntReg, Field::Rs3};
constexpr Operand FS1{OperandKind::FloatReg, Field::Rs1};
constexpr Operand FS2{OperandKind::FloatReg, Field::Rs2};
constexpr Operand FS3{OperandKind::FloatReg, Field::Rs3};
constexpr Operand IMM{OperandKind::Imm, Field::Imm};
constexpr Operand FIMM{OperandKind::FloatImm, Field::Imm};
constexpr Operand MEM{OperandKind::Mem, Field::Imm};
constexpr Operand TGT{OperandKind::Target, Field::Imm};
constexpr Operand CH{OperandKind::Channel, Field::Imm};
constexpr Operand NONE{OperandKind::Imm, Field::Imm};

using C = OpClass;
using K = Kind;

// Row builders keep the table one line per operation.
constexpr OpInfo op(std::string_view m, C c, K k, std::array<Operand, 4> ops, uint8_t n, Eval e,
                    std::string_view sum) {
    return OpInfo{m, c, k, ops, n, e, 0, false, sum};
}
constexpr OpInfo mem(std::string_view m, C c, K k, std::array<Operand, 4> ops, uint8_t bytes,
                     bool sgn, std::string_view sum) {
    return OpInfo{m, c, k, ops, 2, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a + i; },
                  bytes, sgn, sum};
}
constexpr uint32_t zero(uint32_t, uint32_t, uint32_t, uint32_t) { return 0; }
} // namespace detail

// clang-format off
// The operation table. Register operands are listed in assembly order; each names the encoding
// field it occupies. Branch targets are absolute bundle addresses. Conditions live in integer
// registers (no predicate file): compares write 0 or 1, `sel`/`fsel` pick on rc != 0.
inline constexpr auto kOps = [] {
    using namespace detail;
    return std::array{
    // ---- integer ALU -----------------------------------------------------------------------
    op("add",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a + b; }, "rd = rs1 + rs2 (wraps)"),
    op("sub",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a - b; }, "rd = rs1 - rs2 (wraps)"),
    op("and",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a & b; }, "rd = rs1 & rs2"),
    op("or",   C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a | b; }, "rd = rs1 | rs2"),
    op("xor",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a ^ b; }, "rd = rs1 ^ rs2"),
    op("sll",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a << (b & 31); }, "rd = rs1 << (rs2 & 31)"),
    op("srl",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a >> (b & 31); }, "rd = rs1 >> (rs2 & 31), logical"),
    op("sra",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(s(a) >> (b & 31)); }, "rd = rs1 >> (rs2 & 31), arithmetic"),
    op("slt",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(s(a) < s(b)); }, "rd = rs1 < rs2 (signed) ? 1 : 0"),
    op("sltu", C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a < b); }, "rd = rs1 < rs2 (unsigned) ? 1 : 0"),
    op("seq",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a == b); }, "rd = rs1 == rs2 ? 1 : 0"),
    op("sne",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a != b); }, "rd = rs1 != rs2 ? 1 : 0"),
    op("min",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return s(a) < s(b) ? a : b; }, "rd = signed min(rs1, rs2)"),
    op("max",  C::Alu, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return s(a) > s(b) ? a : b; }, "rd = signed max(rs1, rs2)"),
    op("addi", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a + i; }, "rd = rs1 + imm"),
    op("andi", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a & i; }, "rd = rs1 & imm"),
    op("ori",  C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a | i; }, "rd = rs1 | imm"),
    op("xori", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a ^ i; }, "rd = rs1 ^ imm"),
    op("slli", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a << (i & 31); }, "rd = rs1 << (imm & 31)"),
    op("srli", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return a >> (i & 31); }, "rd = rs1 >> (imm & 31), logical"),
    op("srai", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return uint32_t(s(a) >> (i & 31)); }, "rd = rs1 >> (imm & 31), arithmetic"),
    op("slti", C::Alu, K::Compute, {RD, RS1, IMM}, 3, [](uint32_t a, uint32_t, uint32_t, uint32_t i) { return uint32_t(s(a) < s(i)); }, "rd = rs1 < imm (signed) ? 1 : 0"),
    op("li",   C::Alu, K::Compute, {RD, IMM},      2, [](uint32_t, uint32_t, uint32_t, uint32_t i) { return i; }, "rd = imm (any 32-bit value)"),
    op("mov",  C::Alu, K::Compute, {RD, RS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a; }, "rd = rs1"),
    op("sel",  C::Alu, K::Compute, {RD, RS1, RS2, RS3}, 4, [](uint32_t a, uint32_t b, uint32_t c, uint32_t) { return a ? b : c; }, "rd = rs1 != 0 ? rs2 : rs3"),
    op("mul",  C::Mul, K::Compute, {RD, RS1, RS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return a * b; }, "rd = low 32 bits of rs1 * rs2"),
    // ---- floating point (binary32, round to nearest even, subnormals kept) -----------------
    op("fadd", C::FAdd, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return q(f(a) + f(b)); }, "fd = fs1 + fs2"),
    op("fsub", C::FAdd, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return q(f(a) - f(b)); }, "fd = fs1 - fs2"),
    op("fmin", C::FAdd, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return f(a) < f(b) ? a : b; }, "fd = fs1 < fs2 ? fs1 : fs2 (NaN gives fs2)"),
    op("fmax", C::FAdd, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return f(a) > f(b) ? a : b; }, "fd = fs1 > fs2 ? fs1 : fs2 (NaN gives fs2)"),
    op("fabs", C::FAdd, K::Compute, {FD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a & 0x7fffffffu; }, "fd = |fs1| (clears the sign bit)"),
    op("fneg", C::FAdd, K::Compute, {FD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a ^ 0x80000000u; }, "fd = -fs1 (flips the sign bit)"),
    op("fmov", C::FAdd, K::Compute, {FD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a; }, "fd = fs1"),
    op("fli",  C::FAdd, K::Compute, {FD, FIMM},     2, [](uint32_t, uint32_t, uint32_t, uint32_t i) { return i; }, "fd = float immediate"),
    op("fsel", C::FAdd, K::Compute, {FD, RS1, FS2, FS3}, 4, [](uint32_t a, uint32_t b, uint32_t c, uint32_t) { return a ? b : c; }, "fd = rs1 != 0 ? fs2 : fs3"),
    op("flt",  C::FAdd, K::Compute, {RD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(f(a) < f(b)); }, "rd = fs1 < fs2 ? 1 : 0 (NaN gives 0)"),
    op("fle",  C::FAdd, K::Compute, {RD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(f(a) <= f(b)); }, "rd = fs1 <= fs2 ? 1 : 0 (NaN gives 0)"),
    op("feq",  C::FAdd, K::Compute, {RD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(f(a) == f(b)); }, "rd = fs1 == fs2 ? 1 : 0 (NaN gives 0)"),
    op("itof", C::FAdd, K::Compute, {FD, RS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return u(static_cast<float>(s(a))); }, "fd = (float)rs1, round to nearest even"),
    op("ftoi", C::FAdd, K::Compute, {RD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return ftoi(a); }, "rd = (int)fs1, toward zero; saturates; NaN gives 0"),
    op("movif",C::FAdd, K::Compute, {FD, RS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a; }, "fd = bits of rs1"),
    op("movfi",C::FAdd, K::Compute, {RD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return a; }, "rd = bits of fs1"),
    op("fmul", C::FMul, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return q(f(a) * f(b)); }, "fd = fs1 * fs2"),
    op("fdiv", C::FDiv, K::Compute, {FD, FS1, FS2}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return q(f(a) / f(b)); }, "fd = fs1 / fs2"),
    op("fsqrt",C::FDiv, K::Compute, {FD, FS1},      2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return q(std::sqrt(f(a))); }, "fd = sqrt(fs1), correctly rounded"),
    // ---- memory: byte addresses, base + offset; accesses must be aligned -------------------
    mem("lw",  C::Load,  K::Load,  {RD, MEM}, 4, false, "rd = mem32[rs1 + imm]"),
    mem("lh",  C::Load,  K::Load,  {RD, MEM}, 2, true,  "rd = sign-extended mem16[rs1 + imm]"),
    mem("lhu", C::Load,  K::Load,  {RD, MEM}, 2, false, "rd = zero-extended mem16[rs1 + imm]"),
    mem("lb",  C::Load,  K::Load,  {RD, MEM}, 1, true,  "rd = sign-extended mem8[rs1 + imm]"),
    mem("lbu", C::Load,  K::Load,  {RD, MEM}, 1, false, "rd = zero-extended mem8[rs1 + imm]"),
    mem("flw", C::Load,  K::Load,  {FD, MEM}, 4, false, "fd = mem32[rs1 + imm]"),
    mem("sw",  C::Store, K::Store, {RS2, MEM}, 4, false, "mem32[rs1 + imm] = rs2"),
    mem("sh",  C::Store, K::Store, {RS2, MEM}, 2, false, "mem16[rs1 + imm] = low half of rs2"),
    mem("sb",  C::Store, K::Store, {RS2, MEM}, 1, false, "mem8[rs1 + imm] = low byte of rs2"),
    mem("fsw", C::Store, K::Store, {FS2, MEM}, 4, false, "mem32[rs1 + imm] = fs2"),
    // ---- control: a taken branch redirects the next bundle ---------------------------------
    op("beq",  C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a == b); }, "if rs1 == rs2 goto target"),
    op("bne",  C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a != b); }, "if rs1 != rs2 goto target"),
    op("blt",  C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(s(a) < s(b)); }, "if rs1 < rs2 (signed) goto target"),
    op("bge",  C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(s(a) >= s(b)); }, "if rs1 >= rs2 (signed) goto target"),
    op("bltu", C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a < b); }, "if rs1 < rs2 (unsigned) goto target"),
    op("bgeu", C::Branch, K::Branch, {RS1, RS2, TGT}, 3, [](uint32_t a, uint32_t b, uint32_t, uint32_t) { return uint32_t(a >= b); }, "if rs1 >= rs2 (unsigned) goto target"),
    op("beqz", C::Branch, K::Branch, {RS1, TGT}, 2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return uint32_t(a == 0); }, "if rs1 == 0 goto target"),
    op("bnez", C::Branch, K::Branch, {RS1, TGT}, 2, [](uint32_t a, uint32_t, uint32_t, uint32_t) { return uint32_t(a != 0); }, "if rs1 != 0 goto target"),
    op("jmp",  C::Branch, K::Jump,     {TGT}, 1, zero, "goto target"),
    op("jal",  C::Branch, K::JumpLink, {RD, TGT}, 2, zero, "rd = address of next bundle; goto target"),
    op("jr",   C::Branch, K::JumpReg,  {RS1}, 1, zero, "goto rs1"),
    // ---- FIFO channels: `recv` blocks while the channel is empty ---------------------------
    op("recv", C::Fifo, K::Recv, {RD, CH}, 2, zero, "rd = next word from channel"),
    op("frecv",C::Fifo, K::Recv, {FD, CH}, 2, zero, "fd = next word from channel"),
    op("send", C::Fifo, K::Send, {CH, RS1}, 2, zero, "channel <- rs1"),
    op("fsend",C::Fifo, K::Send, {CH, FS1}, 2, zero, "channel <- fs1"),
    // ---- misc ------------------------------------------------------------------------------
    op("nop",  C::Misc, K::Nop,  {}, 0, zero, "no operation (not counted as an operation)"),
    op("halt", C::Misc, K::Halt, {}, 0, zero, "stop this processor"),
    };
}();
// clang-format on

inline constexpr int kNumOps = static_cast<int>(kOps.size());
using Opcode = uint8_t; // index into kOps

constexpr std::optional<Opcode> find_opcode(std::string_view mnemonic) {
    for (int i = 0; i < kNumOps; ++i)
        if (kOps[i].mnemonic == mnemonic) return static_cast<Opcode>(i);
    return std::nullopt;
}

// Compile-time opcode of a mnemonic, for code that names operations (ISS, tests).
consteval Opcode opcode(std::string_view mnemonic) {
    auto op = find_opcode(mnemonic);
    if (!op) throw "unknown mnemonic";
    return *op;
}

// Register-file traffic of one operation: reads at issue, writes when the result lands.
struct PortUse {
    std::array<uint8_t, kNumRegFiles> reads{};
    std::array<uint8_t, kNumRegFiles> writes{};
};

constexpr PortUse port_use(const OpInfo& info) {
    PortUse p;
    for (int i = 0; i < info.num_operands; ++i) {
        const Operand& o = info.operands[i];
        auto count = [&](RegFile rf) {
            auto& slot = o.is_dest ? p.writes : p.reads;
            ++slot[static_cast<int>(rf)];
        };
        if (o.kind == OperandKind::IntReg || o.kind == OperandKind::Mem) count(RegFile::Int);
        if (o.kind == OperandKind::FloatReg) count(RegFile::Float);
    }
    return p;
}

// Compile-time checks on the table itself.
namespace detail {
constexpr bool table_is_consistent() {
    if (kOps.size() > 128) return false; // 7-bit opcode field
    for (int i = 0; i < kNumOps; ++i) {
        const auto& r = kOps[i];
        // (eval != nullptr is checked by a unit test: UBSan makes that comparison non-constant.)
        if (r.mnemonic.empty()) return false;
        for (int j = i + 1; j < kNumOps; ++j)
            if (kOps[j].mnemonic == r.mnemonic) return false;
        // Each encoding field is used by at most one operand.
        unsigned used = 0;
        for (int k = 0; k < r.num_operands; ++k) {
            unsigned bit = 1u << static_cast<int>(r.operands[k].field);
            if (r.operands[k].kind == OperandKind::Mem) bit |= 1u << static_cast<int>(Field::Rs1);
            if (used & bit) return false;
            used |= bit;
            if (r.operands[k].is_dest && r.operands[k].field != Field::Rd) return false;
        }
        if ((r.kind == Kind::Load || r.kind == Kind::Store) &&
            !(r.mem_bytes == 1 || r.mem_bytes == 2 || r.mem_bytes == 4))
            return false;
    }
    return true;
}
static_assert(table_is_consistent(), "kOps: duplicate mnemonic, field clash or bad row");
} // namespace detail

} // namespace nesshi::isa
