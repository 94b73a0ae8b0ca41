// Parsed source records: plain data that keeps its source location; built by the parser,
// laid out by layout.cpp and encoded by the assembler driver.
#pragma once

#include "lexer.hpp"
#include "source.hpp"

#include "isa/encoding.hpp"

#include <string>
#include <vector>

namespace nesshi::assembler {

// The immediate part of an operation, evaluated in the second pass (it may name labels).
struct ImmRec {
    bool present = false;
    isa::OperandKind kind = isa::OperandKind::Imm;
    std::vector<Token> expr; // empty with literal_bits set: a float literal already converted
    bool literal = false;
    uint32_t literal_bits = 0;
    Loc loc;
};

struct OpRec {
    Loc loc;          // first character of the operation (slot prefix or mnemonic)
    std::string text; // the operation as written
    int pin = -1;     // slot index given by a `slot:` prefix
    isa::Instr instr; // registers filled at parse time, imm in the second pass
    ImmRec imm;
};

struct BundleRec {
    Loc loc; // the `{` or the single operation
    std::vector<OpRec> ops;
    bool had_errors = false; // some operation was dropped: skip resource checks
};

struct DirectiveRec {
    Loc loc;
    std::string name;                      // with the leading '.'
    std::vector<std::vector<Token>> args;  // split at top-level commas
    std::vector<Loc> arg_locs;
};

struct LabelRec {
    Loc loc;
    std::string name;
};

struct Item {
    enum class Kind { Label, Directive, Bundle } kind;
    LabelRec label;
    DirectiveRec directive;
    BundleRec bundle;
};

} // namespace nesshi::assembler
