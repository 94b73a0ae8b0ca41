// Operation syntax from the kOps table: one generic matcher, no per-operation parsing code.
#pragma once

#include "expr.hpp"
#include "records.hpp"

#include "isa/machine.hpp"

#include <optional>
#include <span>
#include <string>

namespace nesshi::assembler {

// The syntax of a row's operands, e.g. "fd, fs1, fs2" (for messages).
std::string operand_syntax(const isa::OpInfo& info);

// Parses `mnemonic operand, ...` (tokens after any slot prefix) into an OpRec; registers are
// checked against the machine here, immediates are kept as expressions for the second pass.
// Reports problems to `diags` and returns nullopt when the operation cannot be built.
std::optional<OpRec> parse_op(std::span<const Token> toks, int file, int line,
                              const isa::Machine& m, Diagnostics& diags);

// Converts a float immediate (`1.5`, `-2`, `1e-3`) to its binary32 bits; nullopt with `err`
// set when it is not a float literal of that form.
std::optional<uint32_t> float_literal(std::span<const Token> toks, std::string& err);

// Evaluates an operation's immediate (second pass) and stores it in rec.instr.imm. Range rules
// per operand kind: immediates and offsets fit 32 bits (signed or unsigned), targets are
// bundle indices inside the code, channels are non-negative.
bool resolve_imm(OpRec& rec, const Resolver& resolve, size_t bundle_count, Diagnostics& diags);

} // namespace nesshi::assembler
