// Generic operand matcher driven by isa::kOps (see operands.hpp).
#include "operands.hpp"

#include "expr.hpp"

#include "base/suggest.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace nesshi::assembler {

using isa::Field;
using isa::OperandKind;

namespace {

std::string_view field_name(Field f) {
    switch (f) {
    case Field::Rd: return "d";
    case Field::Rs1: return "s1";
    case Field::Rs2: return "s2";
    case Field::Rs3: return "s3";
    case Field::Imm: return "imm";
    }
    return "?";
}

std::string operand_name(const isa::Operand& o) {
    switch (o.kind) {
    case OperandKind::IntReg: return fmt::format("r{}", field_name(o.field));
    case OperandKind::FloatReg: return fmt::format("f{}", field_name(o.field));
    case OperandKind::Imm: return "imm";
    case OperandKind::FloatImm: return "fimm";
    case OperandKind::Mem: return "imm(rs1)";
    case OperandKind::Target: return "target";
    case OperandKind::Channel: return "channel";
    }
    return "?";
}

std::string_view kind_words(OperandKind k) {
    switch (k) {
    case OperandKind::IntReg: return "an integer register";
    case OperandKind::FloatReg: return "a float register";
    case OperandKind::Imm: return "an immediate";
    case OperandKind::FloatImm: return "a float immediate";
    case OperandKind::Mem: return "a memory operand imm(rN)";
    case OperandKind::Target: return "a branch target";
    case OperandKind::Channel: return "a channel number";
    }
    return "?";
}

Loc at(int file, int line, const Token& t) { return Loc{file, line, t.col}; }

// Splits tokens at top-level commas.
std::vector<std::span<const Token>> split_commas(std::span<const Token> toks) {
    std::vector<std::span<const Token>> out;
    int depth = 0;
    size_t start = 0;
    for (size_t i = 0; i < toks.size(); ++i) {
        if (toks[i].is("(")) ++depth;
        if (toks[i].is(")")) --depth;
        if (depth == 0 && toks[i].is(",")) {
            out.push_back(toks.subspan(start, i - start));
            start = i + 1;
        }
    }
    out.push_back(toks.subspan(start));
    return out;
}

// A register name rN / fN; returns the number or -1; `file` receives 'r' or 'f'.
int register_number(const Token& t, char& file) {
    if (t.kind != Tok::Ident || t.text.size() < 2 || t.text.size() > 5) return -1;
    if (t.text[0] != 'r' && t.text[0] != 'f') return -1;
    int n = 0;
    for (size_t i = 1; i < t.text.size(); ++i) {
        if (t.text[i] < '0' || t.text[i] > '9') return -1;
        n = n * 10 + (t.text[i] - '0');
    }
    file = t.text[0];
    return n;
}

void set_field(isa::Instr& in, Field f, uint8_t v) {
    switch (f) {
    case Field::Rd: in.rd = v; break;
    case Field::Rs1: in.rs1 = v; break;
    case Field::Rs2: in.rs2 = v; break;
    case Field::Rs3: in.rs3 = v; break;
    case Field::Imm: break;
    }
}

struct OpParser {
    int file, line;
    const isa::Machine& m;
    Diagnostics& diags;
    std::string_view mnemonic;

    bool reg(std::span<const Token> toks, OperandKind kind, Field f, isa::Instr& in, Loc loc) {
        char rf = 0;
        int n = toks.size() == 1 ? register_number(toks[0], rf) : -1;
        char want = kind == OperandKind::IntReg ? 'r' : 'f';
        if (n < 0 || rf != want) {
            diags.error(loc, fmt::format("'{}' expects {} here, found '{}'", mnemonic,
                                         kind_words(kind), spelled(toks)));
            return false;
        }
        auto rfile = kind == OperandKind::IntReg ? isa::RegFile::Int : isa::RegFile::Float;
        uint32_t count = m.regfile(rfile).count;
        if (n >= isa::kMaxRegs || uint32_t(n) >= count) {
            diags.error(loc, fmt::format("register {}{} out of range: {} has {}0..{}{}", want, n, m.name,
                                         want, want, std::min<uint32_t>(count, isa::kMaxRegs) - 1));
            return false;
        }
        set_field(in, f, uint8_t(n));
        return true;
    }

    static std::string spelled(std::span<const Token> toks) {
        std::string s;
        for (const auto& t : toks) {
            if (!s.empty() && t.kind != Tok::Punct && s.back() != '(' && s.back() != '-') s += ' ';
            s += t.kind == Tok::String ? "\"" + t.text + "\"" : t.text;
        }
        return s.empty() ? "nothing" : s;
    }

    bool operand(std::span<const Token> toks, const isa::Operand& o, OpRec& rec, Loc loc) {
        if (toks.empty()) {
            diags.error(loc, fmt::format("'{}' expects {} here, found nothing", mnemonic, kind_words(o.kind)));
            return false;
        }
        switch (o.kind) {
        case OperandKind::IntReg:
        case OperandKind::FloatReg: return reg(toks, o.kind, o.field, rec.instr, loc);
        case OperandKind::Mem: {
            size_t n = toks.size();
            if (n < 3 || !toks[n - 3].is("(") || !toks[n - 1].is(")")) {
                diags.error(loc, fmt::format("'{}' expects a memory operand imm(rN), found '{}'",
                                             mnemonic, spelled(toks)));
                return false;
            }
            if (!reg(toks.subspan(n - 2, 1), OperandKind::IntReg, Field::Rs1, rec.instr,
                     at(file, line, toks[n - 2])))
                return false;
            auto off = toks.first(n - 3);
            if (!off.empty() && !is_expr(off)) {
                diags.error(loc, fmt::format("malformed memory offset '{}'", spelled(off)));
                return false;
            }
            rec.imm = {true, o.kind, {off.begin(), off.end()}, off.empty(), 0, loc};
            return true;
        }
        case OperandKind::FloatImm: {
            std::string err;
            if (auto bits = float_literal(toks, err)) {
                rec.imm = {true, o.kind, {}, true, *bits, loc};
                return true;
            }
            if (!err.empty()) {
                diags.error(loc, err);
                return false;
            }
            [[fallthrough]];
        }
        case OperandKind::Imm:
        case OperandKind::Target:
        case OperandKind::Channel:
            if (!is_expr(toks)) {
                diags.error(loc, fmt::format("'{}' expects {} here, found '{}'", mnemonic,
                                             kind_words(o.kind), spelled(toks)));
                return false;
            }
            rec.imm = {true, o.kind, {toks.begin(), toks.end()}, false, 0, loc};
            return true;
        }
        return false;
    }
};

} // namespace

std::string operand_syntax(const isa::OpInfo& info) {
    std::string s;
    for (int i = 0; i < info.num_operands; ++i) {
        if (i) s += ", ";
        s += operand_name(info.operands[size_t(i)]);
    }
    return s;
}

std::optional<uint32_t> float_literal(std::span<const Token> toks, std::string& err) {
    bool neg = false;
    if (!toks.empty() && toks[0].is("-")) {
        neg = true;
        toks = toks.subspan(1);
    }
    if (toks.size() != 1) return std::nullopt;
    const Token& t = toks[0];
    bool decimal_int = t.kind == Tok::Int && !t.text.empty() && t.text[0] >= '0' && t.text[0] <= '9' &&
                       (t.text.size() < 2 || (t.text[1] != 'x' && t.text[1] != 'X' && t.text[1] != 'b' && t.text[1] != 'B'));
    if (t.kind != Tok::Float && !decimal_int) return std::nullopt;
    errno = 0;
    char* end = nullptr;
    float v = std::strtof(t.text.c_str(), &end);
    if (end != t.text.c_str() + t.text.size()) {
        err = fmt::format("malformed float literal '{}'", t.text);
        return std::nullopt;
    }
    if (std::isinf(v)) {
        err = fmt::format("float literal '{}' is out of range for binary32", t.text);
        return std::nullopt;
    }
    uint32_t bits = std::bit_cast<uint32_t>(v);
    if (neg) bits ^= 0x80000000u;
    return bits;
}

std::optional<OpRec> parse_op(std::span<const Token> toks, int file, int line,
                              const isa::Machine& m, Diagnostics& diags) {
    const Token& mn = toks[0];
    Loc loc = at(file, line, mn);
    if (mn.kind != Tok::Ident) {
        diags.error(loc, fmt::format("expected an operation, found '{}'", mn.text));
        return std::nullopt;
    }
    auto opc = isa::find_opcode(mn.text);
    if (!opc) {
        std::vector<std::string> names;
        for (const isa::OpInfo& o : isa::kOps) names.emplace_back(o.mnemonic);
        diags.error(loc, fmt::format("unknown operation '{}'{}", mn.text, base::did_you_mean(mn.text, names)));
        return std::nullopt;
    }
    const isa::OpInfo& info = isa::kOps[*opc];
    OpRec rec;
    rec.loc = loc;
    rec.instr.opcode = *opc;
    auto rest = toks.subspan(1);
    auto parts = rest.empty() ? std::vector<std::span<const Token>>{} : split_commas(rest);
    for (const auto& t : rest)
        if (t.kind == Tok::Bad) {
            diags.error(at(file, line, t), t.text);
            return std::nullopt;
        }
    if (int(parts.size()) != info.num_operands) {
        diags.error(loc, info.num_operands == 0
                             ? fmt::format("'{}' takes no operands", info.mnemonic)
                             : fmt::format("'{}' takes {} operand{} ({}), found {}", info.mnemonic,
                                           info.num_operands, info.num_operands == 1 ? "" : "s",
                                           operand_syntax(info), parts.size()));
        return std::nullopt;
    }
    OpParser p{file, line, m, diags, info.mnemonic};
    bool ok = true;
    for (size_t i = 0; i < parts.size(); ++i) {
        Loc oloc = parts[i].empty() ? loc : at(file, line, parts[i][0]);
        ok = p.operand(parts[i], info.operands[i], rec, oloc) && ok;
    }
    if (!ok) return std::nullopt;
    return rec;
}

bool resolve_imm(OpRec& rec, const Resolver& resolve, size_t bundle_count, Diagnostics& diags) {
    ImmRec& im = rec.imm;
    if (!im.present) return true;
    if (im.literal) {
        rec.instr.imm = im.literal_bits;
        return true;
    }
    ExprResult r = eval_expr(im.expr, resolve);
    if (!r.ok) {
        diags.error(Loc{im.loc.file, im.loc.line, r.col}, r.error);
        return false;
    }
    int64_t v = r.value;
    std::string_view what = im.kind == OperandKind::Mem ? "memory offset" : "immediate";
    switch (im.kind) {
    case OperandKind::Target:
        if (v < 0 || uint64_t(v) >= bundle_count) {
            diags.error(im.loc, fmt::format("branch target {} is outside the code (bundles 0..{})", v,
                                            int64_t(bundle_count) - 1));
            return false;
        }
        break;
    case OperandKind::Channel:
        if (v < 0 || v > int64_t(UINT32_MAX)) {
            diags.error(im.loc, fmt::format("channel {} out of range (0..{})", v, UINT32_MAX));
            return false;
        }
        break;
    default:
        if (v < INT32_MIN || v > int64_t(UINT32_MAX)) {
            diags.error(im.loc, fmt::format("{} {} does not fit in 32 bits", what, v));
            return false;
        }
        break;
    }
    rec.instr.imm = uint32_t(uint64_t(v));
    return true;
}

} // namespace nesshi::assembler
