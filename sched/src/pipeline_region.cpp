#include "pipeline_region.hpp"

#include "text.hpp"

#include "assembler/assembler.hpp"
#include "assembler/op_text.hpp"
#include "base/error.hpp"
#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cctype>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <regex>
#include <set>
#include <stdexcept>
#include <tuple>

namespace nesshi::sched::pipe {

[[noreturn]] void fail(std::string_view file, int line, const std::string& msg) {
    throw base::Error(base::SourceLoc(file, line), msg);
}

char file_prefix(isa::RegFile f) { return f == isa::RegFile::Int ? 'r' : 'f'; }
std::string reg_name(isa::RegFile f, int r) { return fmt::format("{}{}", file_prefix(f), r); }

bool opens_region(const std::string& code) {
    return code.rfind(".pipeline", 0) == 0 && (code.size() == 9 || std::isspace(static_cast<unsigned char>(code[9])));
}

// The line indices of each region's .pipeline and .endpipeline, in file order.
std::vector<Span> region_spans(const std::vector<std::string>& lines, std::string_view file) {
    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    std::vector<Span> spans;
    std::size_t open = kNone;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string code = strip_comment(lines[i]);
        const int ln = static_cast<int>(i + 1);
        if (opens_region(code)) {
            if (open != kNone) fail(file, ln, fmt::format(".pipeline inside the region opened at line {} (regions do not nest)", open + 1));
            open = i;
        } else if (code == ".endpipeline") {
            if (open == kNone) fail(file, ln, ".endpipeline without .pipeline");
            spans.emplace_back(open, i);
            open = kNone;
        }
    }
    if (open != kNone) fail(file, static_cast<int>(open + 1), ".pipeline without .endpipeline");
    if (spans.empty()) fail(file, 0, "no .pipeline region");
    return spans;
}

namespace {
// The operands of an operation or directive line, as the assembler splits them.
std::vector<std::string> operands_of(const std::string& code) {
    std::vector<std::string> out;
    for (const assembler::OperandText& o : assembler::split_operation(code).operands) out.push_back(o.text);
    return out;
}
} // namespace

Region parse_region(const std::vector<std::string>& lines, std::string_view file, Span span) {
    Region r;
    bool found = false, closed = false;
    for (std::size_t i = span.first; i <= span.second; ++i) {
        const std::string code = strip_comment(lines[i]);
        const int ln = static_cast<int>(i + 1);
        if (opens_region(code)) {
            found = true;
            r.begin = i;
            r.trip = trim(code.substr(9));
            if (r.trip == "while") {
                r.is_while = true;
                r.trip.clear();
                r.trip_reg = -1;
                continue;
            }
            const auto reg = assembler::register_named(r.trip);
            if (!reg || reg->first != isa::RegFile::Int)
                fail(file, ln, fmt::format(".pipeline takes the integer register holding the trip count, not '{}'", r.trip));
            r.trip_reg = reg->second;
            continue;
        }
        if (code == ".endpipeline") {
            if (!found || closed) fail(file, ln, ".endpipeline without .pipeline");
            closed = true;
            r.end = i;
            continue;
        }
        if (!found || closed || code.empty()) continue;
        if (code.rfind(".noalias", 0) == 0) {
            const auto regs = operands_of(code);
            const auto a = regs.size() == 2 ? assembler::register_named(regs[0]) : std::nullopt;
            const auto b = regs.size() == 2 ? assembler::register_named(regs[1]) : std::nullopt;
            if (!a || !b || a->first != isa::RegFile::Int || b->first != isa::RegFile::Int)
                fail(file, ln, ".noalias takes two integer base registers: .noalias rA, rB");
            r.noalias.emplace_back(a->second, b->second);
            continue;
        }
        if (code.rfind(".trip", 0) == 0 && (code.size() == 5 || std::isspace(static_cast<unsigned char>(code[5])))) {
            if (r.is_while) fail(file, ln, ".trip belongs in a counted .pipeline region (a while loop has no trip count)");
            if (r.trip_count.min > 0) fail(file, ln, fmt::format(".trip given twice (first at line {})", r.trip_count.line));
            r.trip_count = parse_trip(lines[i], file, ln);
            continue;
        }
        if (code.rfind(".speculate", 0) == 0) {
            if (!r.is_while) fail(file, ln, ".speculate belongs in a .pipeline while region");
            for (const std::string& reg : operands_of(code)) {
                if (!reg.empty() && reg[0] == '%') { // a base computed or loaded in the loop: checked once the region is read
                    r.speculate_virtual.insert(reg);
                    continue;
                }
                const auto b = assembler::register_named(reg);
                if (!b || b->first != isa::RegFile::Int)
                    fail(file, ln, ".speculate takes integer base registers: .speculate rA[, %p ...]");
                r.speculate.insert(b->second);
            }
            r.line_of_speculate = ln;
            continue;
        }
        if (code.rfind(".carry", 0) == 0 || code.rfind(".liveout", 0) == 0) {
            const bool carry = code[1] == 'c';
            if (!r.is_while)
                fail(file, ln, fmt::format("{} belongs in a .pipeline while region (not yet in counted loops)",
                                           carry ? ".carry" : ".liveout"));
            const auto args = operands_of(code);
            if (args.empty() || args[0].empty() || args[0][0] != '%' || args.size() < 2 || args.size() > (carry ? 4u : 2u))
                fail(file, ln, carry ? ".carry takes a virtual register and its registers: .carry %v, IN[, OUT[, OLD]]"
                                     : ".liveout takes a virtual register and where it ends: .liveout %v, REG");
            for (std::size_t k = 1; k < args.size(); ++k)
                if (!assembler::register_named(args[k])) fail(file, ln, fmt::format("'{}' is not a register", args[k]));
            if (r.carry.count(args[0]) || r.liveout.count(args[0])) fail(file, ln, fmt::format("{} is declared twice", args[0]));
            if (carry) r.carry[args[0]] = {args[1], args.size() > 2 ? args[2] : args[1], args.size() > 3 ? args[3] : ""};
            else r.liveout[args[0]] = args[1];
            r.line_of_directives = ln;
            continue;
        }
        if (code.find('{') != std::string::npos || code.find('}') != std::string::npos)
            fail(file, ln, "a .pipeline region holds one operation per line, no bundles");
        if (code.find(':') != std::string::npos) fail(file, ln, "no labels or slot prefixes inside a .pipeline region");
        SrcOp op;
        op.line = ln;
        op.mnemonic = assembler::split_operation(code).mnemonic;
        op.operands = operands_of(code);
        const auto opc = isa::find_opcode(op.mnemonic);
        if (!opc) fail(file, ln, fmt::format("unknown operation '{}'", op.mnemonic));
        op.opcode = *opc;
        const isa::OpInfo& info = isa::kOps[*opc];
        const bool conditional = info.kind == isa::Kind::Branch && op.mnemonic != "jmp" && op.mnemonic != "jal";
        if (r.is_while && conditional && !op.operands.empty() && op.operands.back() == "exit") {
            if (r.exit_op >= 0) fail(file, ln, "a .pipeline while region has one exit test; this is a second");
            r.exit_op = static_cast<int>(r.ops.size());
        } else switch (info.kind) {
        case isa::Kind::Branch:
        case isa::Kind::Jump:
        case isa::Kind::JumpLink:
        case isa::Kind::JumpReg:
        case isa::Kind::Halt:
            fail(file, ln, fmt::format("'{}': no control flow inside a .pipeline region (the tool makes the loop){}",
                                       op.mnemonic, r.is_while ? "; the exit test is a conditional branch to 'exit'" : ""));
        default: break;
        }
        if (op.operands.size() != info.num_operands)
            fail(file, ln, fmt::format("'{}' takes {} operands", op.mnemonic, info.num_operands));
        const int index = static_cast<int>(r.ops.size());
        std::vector<std::size_t> order; // sources first: an op reads before its own result exists
        for (std::size_t k = 0; k < op.operands.size(); ++k)
            if (!info.operands[k].is_dest) order.push_back(k);
        for (std::size_t k = 0; k < op.operands.size(); ++k)
            if (info.operands[k].is_dest) order.push_back(k);
        for (std::size_t k : order) {
            const std::string& o = op.operands[k];
            const std::size_t pct = o.find('%');
            if (pct == std::string::npos) continue;
            std::size_t e = pct + 1;
            while (e < o.size() && (std::isalnum(static_cast<unsigned char>(o[e])) || o[e] == '_')) ++e;
            const std::string name = o.substr(pct, e - pct);
            const isa::Operand& desc = info.operands[k];
            isa::RegFile f;
            if (desc.kind == isa::OperandKind::IntReg || desc.kind == isa::OperandKind::Mem) f = isa::RegFile::Int;
            else if (desc.kind == isa::OperandKind::FloatReg) f = isa::RegFile::Float;
            else fail(file, ln, fmt::format("{}: a virtual register where '{}' takes no register", name, op.mnemonic));
            if (desc.kind == isa::OperandKind::Mem && o.find('(') > pct)
                fail(file, ln, fmt::format("{}: a virtual register in an offset", name));
            auto [it, fresh] = r.virtual_index.emplace(name, static_cast<int>(r.virtuals.size()));
            if (fresh) r.virtuals.push_back({name, f, -1});
            Virtual& v = r.virtuals[static_cast<std::size_t>(it->second)];
            if (v.file != f) fail(file, ln, fmt::format("{} is used both as an integer and as a float register", name));
            if (desc.is_dest) {
                if (v.def >= 0) fail(file, ln, fmt::format("{} is written twice in one iteration; name each value once", name));
                v.def = index;
            } else if (v.def < 0 && !r.carry.count(name)) {
                fail(file, ln, fmt::format("{} is read before it is written: a value carried from one iteration to the "
                                           "next must live in a physical register (e.g. an accumulator)",
                                           name));
            }
        }
        r.ops.push_back(std::move(op));
    }
    if (!found) fail(file, 0, "no .pipeline region");
    if (!closed) fail(file, static_cast<int>(r.begin + 1), ".pipeline without .endpipeline");
    if (r.ops.empty()) fail(file, static_cast<int>(r.begin + 1), "the .pipeline region is empty");
    if (r.is_while && r.exit_op < 0)
        fail(file, static_cast<int>(r.begin + 1), ".pipeline while needs an exit test: a conditional branch to 'exit' "
                                                  "(e.g. beqz %go, exit)");
    auto declared = [&](const std::string& name, const std::vector<std::string>& regs) {
        const auto it = r.virtual_index.find(name);
        if (it == r.virtual_index.end() || r.virtuals[static_cast<std::size_t>(it->second)].def < 0)
            fail(file, r.line_of_directives, fmt::format("{} is declared but never written in the region", name));
        const Virtual& v = r.virtuals[static_cast<std::size_t>(it->second)];
        for (const std::string& reg : regs) {
            const auto named = assembler::register_named(reg);
            if (named && named->first != v.file)
                fail(file, r.line_of_directives, fmt::format("{} and {} are not in the same register file", name, reg));
        }
        return v;
    };
    for (const auto& [name, c] : r.carry) declared(name, {c.in, c.out, c.old});
    for (const std::string& name : r.speculate_virtual) {
        const auto it = r.virtual_index.find(name);
        if (it == r.virtual_index.end() || r.virtuals[static_cast<std::size_t>(it->second)].file != isa::RegFile::Int)
            fail(file, r.line_of_speculate, fmt::format("{} in .speculate is no integer virtual register of the region", name));
    }
    for (const auto& [name, reg] : r.liveout)
        if (declared(name, {reg}).def > r.exit_op)
            fail(file, r.line_of_directives, fmt::format("{} is written after the exit test: the exiting iteration has no "
                                                         "value of it", name));
    return r;
}

// Registers the source names anywhere outside comments (never allocated by the tool).
std::set<std::pair<int, int>> named_registers(const std::vector<std::string>& lines) {
    std::set<std::pair<int, int>> used;
    static const std::regex re(R"((^|[^A-Za-z0-9_%])([rf])([0-9]+)\b)");
    for (const std::string& l : lines) {
        const std::string code = strip_comment(l);
        for (auto it = std::sregex_iterator(code.begin(), code.end(), re); it != std::sregex_iterator(); ++it) {
            const int reg = std::stoi((*it)[3].str());
            used.insert({(*it)[2].str() == "r" ? 0 : 1, reg});
        }
    }
    return used;
}

// The first register the file names that m does not have, reported as the assembler would (line,
// caret), before virtual registers are placed, which would only find too few free ones.
void check_named_in_range(const std::vector<std::string>& lines, std::string_view filename, const isa::Machine& m) {
    static const std::regex re(R"((^|[^A-Za-z0-9_%])([rf])([0-9]+)\b)");
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string code = strip_comment(lines[i]);
        for (auto it = std::sregex_iterator(code.begin(), code.end(), re); it != std::sregex_iterator(); ++it) {
            const std::string want = (*it)[2].str();
            const int reg = std::stoi((*it)[3].str());
            const std::uint32_t count = m.regs[want == "r" ? 0 : 1].count;
            if (reg < static_cast<int>(count)) continue;
            const auto col = static_cast<int>(lines[i].find(code) + static_cast<std::size_t>(it->position(2)) + 1);
            throw base::Error(base::SourceLoc(filename, static_cast<int>(i + 1), col),
                              fmt::format("register {}{} out of range: {} has {}0..{}{}\n{}\n{}^", want, reg, m.name, want, want,
                                          std::min<std::uint32_t>(count, isa::kMaxRegs) - 1, lines[i],
                                          std::string(static_cast<std::size_t>(col - 1), ' ')));
        }
    }
}

// The op's source text with virtual registers replaced and the memory offset moved by `delta`.
// `prev` (with the op's index): the registers of the previous iteration, which a read of a
// carried virtual register before its write in the body sees.
std::string op_text(const SrcOp& op, const Region& r, const std::vector<std::string>& vreg, std::int64_t delta,
                    const std::vector<std::string>* prev, int index) {
    std::string out = op.mnemonic;
    const isa::OpInfo& info = isa::kOps[op.opcode];
    for (std::size_t k = 0; k < op.operands.size(); ++k) {
        std::string o = op.operands[k];
        for (std::size_t p; (p = o.find('%')) != std::string::npos;) {
            std::size_t e = p + 1;
            while (e < o.size() && (std::isalnum(static_cast<unsigned char>(o[e])) || o[e] == '_')) ++e;
            const std::size_t v = static_cast<std::size_t>(r.virtual_index.at(o.substr(p, e - p)));
            const bool old = prev && !info.operands[k].is_dest && r.virtuals[v].def >= index;
            o = o.substr(0, p) + (old ? (*prev)[v] : vreg[v]) + o.substr(e);
        }
        if (info.operands[k].kind == isa::OperandKind::Mem && delta != 0) {
            const std::size_t paren = o.find('(');
            const std::string expr = trim(o.substr(0, paren));
            o = (expr.empty() ? fmt::format("{}", delta) : fmt::format("{}{:+}", expr, delta)) + o.substr(paren);
        }
        out += (k == 0 ? " " : ", ") + o;
    }
    return out;
}

} // namespace nesshi::sched::pipe
