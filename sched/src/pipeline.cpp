// Software pipelining from linear assembly (see pipeline.hpp): parse the region, assemble its
// sequential meaning to get exact operations, build the dependence graph, modulo-schedule it,
// allocate registers and emit prologue, kernel and epilogue as assembly text.
#include "sched/pipeline.hpp"

#include "circuits.hpp"
#include "stages.hpp"
#include "text.hpp"
#include "trip.hpp"
#include "sched/block.hpp"
#include "sched/bounds.hpp"
#include "sched/loop_report.hpp"

#include "assembler/assembler.hpp"
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
#include <functional>
#include <cctype>
#include <map>
#include <numeric>
#include <random>
#include <regex>
#include <set>
#include <stdexcept>
#include <tuple>

namespace nesshi::sched {

namespace {

constexpr int kMaxDistance = 16;  // memory dependences are looked for up to this many iterations apart
constexpr int kAttemptsPerII = 12; // schedules tried at one II before the next (different op orders)
constexpr int kMaxBubbleUnroll = 8; // kernel copies a while loop may get for its branch bubble
constexpr int kMaxPortUnroll = 16;  // kernel copies any loop may get to keep writes off one port

[[noreturn]] void fail(std::string_view file, int line, const std::string& msg) {
    throw base::Error(base::SourceLoc(file, line), msg);
}

// A schedule whose copies of the virtual registers do not fit the register files: that schedule
// fails, not the search (another op order or a larger II has shorter lifetimes).
class RegisterPressure : public base::Error {
  public:
    using base::Error::Error;
};

char file_prefix(isa::RegFile f) { return f == isa::RegFile::Int ? 'r' : 'f'; }
std::string reg_name(isa::RegFile f, int r) { return fmt::format("{}{}", file_prefix(f), r); }


// ---- the region -------------------------------------------------------------------------------

struct SrcOp {
    int line = 0;
    std::string mnemonic;
    std::vector<std::string> operands; // as written, trimmed
    isa::Opcode opcode = 0;
};

struct Virtual {
    std::string name;
    isa::RegFile file = isa::RegFile::Int;
    int def = -1; // the op defining it
};

// The placeholder registers (file, register) of one op's operands and the virtual each stands for.
using OpVirtuals = std::map<std::pair<int, int>, int>;

struct Region {
    std::size_t begin = 0, end = 0; // line indices of .pipeline and .endpipeline
    std::string trip;               // the trip-count register, "r9"
    int trip_reg = 0;
    std::vector<SrcOp> ops;
    std::vector<Virtual> virtuals;
    std::map<std::string, int> virtual_index;
    std::vector<std::pair<int, int>> noalias; // int register pairs
    // `.pipeline while`: no trip count; the one exit test is the conditional branch to `exit`.
    bool is_while = false;
    int exit_op = -1;
    std::set<int> speculate; // `.speculate rA`: loads based on rA may run ahead of the exit
    std::set<std::string> speculate_virtual; // `.speculate %p`: loads based on the virtual %p too
    // `.carry %v, IN[, OUT[, OLD]]`: %v is carried from one iteration to the next (read before its
    // write), starts as IN, ends in OUT (default IN) and, in OLD, the value the exiting iteration
    // started with. `.liveout %v, REG`: the exiting iteration's %v ends in REG.
    struct Carry {
        std::string in, out, old;
    };
    std::map<std::string, Carry> carry;
    std::map<std::string, std::string> liveout;
    int line_of_directives = 0, line_of_speculate = 0;
    TripDirective trip_count; // `.trip MIN[, EXPECTED]` (counted loops)
};

bool opens_region(const std::string& code) {
    return code.rfind(".pipeline", 0) == 0 && (code.size() == 9 || std::isspace(static_cast<unsigned char>(code[9])));
}

// The line indices of each region's .pipeline and .endpipeline, in file order.
using Span = std::pair<std::size_t, std::size_t>;
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
            isa::RegFile f;
            if (!parse_reg(r.trip, f, r.trip_reg) || f != isa::RegFile::Int)
                fail(file, ln, fmt::format(".pipeline takes the integer register holding the trip count, not '{}'", r.trip));
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
            const auto regs = split_operands(code.substr(8));
            isa::RegFile fa, fb;
            int a = 0, b = 0;
            if (regs.size() != 2 || !parse_reg(regs[0], fa, a) || !parse_reg(regs[1], fb, b) ||
                fa != isa::RegFile::Int || fb != isa::RegFile::Int)
                fail(file, ln, ".noalias takes two integer base registers: .noalias rA, rB");
            r.noalias.emplace_back(a, b);
            continue;
        }
        if (code.rfind(".trip", 0) == 0 && (code.size() == 5 || std::isspace(static_cast<unsigned char>(code[5])))) {
            if (r.is_while) fail(file, ln, ".trip belongs in a counted .pipeline region (a while loop has no trip count)");
            if (r.trip_count.min > 0) fail(file, ln, fmt::format(".trip given twice (first at line {})", r.trip_count.line));
            r.trip_count = parse_trip(code, lines[i], file, ln);
            continue;
        }
        if (code.rfind(".speculate", 0) == 0) {
            if (!r.is_while) fail(file, ln, ".speculate belongs in a .pipeline while region");
            for (const std::string& reg : split_operands(code.substr(10))) {
                isa::RegFile f;
                int b = 0;
                if (!reg.empty() && reg[0] == '%') { // a base computed or loaded in the loop: checked once the region is read
                    r.speculate_virtual.insert(reg);
                    continue;
                }
                if (!parse_reg(reg, f, b) || f != isa::RegFile::Int)
                    fail(file, ln, ".speculate takes integer base registers: .speculate rA[, %p ...]");
                r.speculate.insert(b);
            }
            r.line_of_speculate = ln;
            continue;
        }
        if (code.rfind(".carry", 0) == 0 || code.rfind(".liveout", 0) == 0) {
            const bool carry = code[1] == 'c';
            if (!r.is_while)
                fail(file, ln, fmt::format("{} belongs in a .pipeline while region (not yet in counted loops)",
                                           carry ? ".carry" : ".liveout"));
            const auto args = split_operands(code.substr(carry ? 6 : 8));
            if (args.empty() || args[0].empty() || args[0][0] != '%' || args.size() < 2 || args.size() > (carry ? 4u : 2u))
                fail(file, ln, carry ? ".carry takes a virtual register and its registers: .carry %v, IN[, OUT[, OLD]]"
                                     : ".liveout takes a virtual register and where it ends: .liveout %v, REG");
            for (std::size_t k = 1; k < args.size(); ++k) {
                isa::RegFile f;
                int reg = 0;
                if (!parse_reg(args[k], f, reg)) fail(file, ln, fmt::format("'{}' is not a register", args[k]));
            }
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
        const std::size_t sp = code.find_first_of(" \t");
        op.mnemonic = code.substr(0, sp);
        op.operands = split_operands(sp == std::string::npos ? "" : code.substr(sp));
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
            isa::RegFile f;
            int n = 0;
            if (!reg.empty() && parse_reg(reg, f, n) && f != v.file)
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

// ---- text of one operation --------------------------------------------------------------------

// The op's source text with virtual registers replaced and the memory offset moved by `delta`.
// `prev` (with the op's index): the registers of the previous iteration, which a read of a
// carried virtual register before its write in the body sees.
std::string op_text(const SrcOp& op, const Region& r, const std::vector<std::string>& vreg, std::int64_t delta,
                    const std::vector<std::string>* prev = nullptr, int index = -1) {
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

// ---- the graph ------------------------------------------------------------------------------

struct Edge {
    int from, to;
    int latency;  // to issues >= from's issue + latency - distance * II
    int distance; // iterations
    std::string why;
};

struct Node {
    isa::Instr instr;
    int latency = 1;
    bool mem = false, store = false;
    int base = -1;            // memory ops: the base register
    bool speculative = false; // a load whose base is declared `.speculate` (it may run past the exit)
    bool adjusted = false;    // memory op on an induction register: offset moved, no register edge
    int width = 4;
};

struct Induction {
    int reg = -1;
    int op = -1;      // the addi
    std::int64_t step = 0;
};

struct Graph {
    std::vector<Node> nodes;
    std::vector<Edge> edges;
    std::vector<Induction> inductions;
    // What the code before the region leaves: integer registers holding known constants, and the
    // trip count when it is one of them (constants_at).
    std::map<int, std::int64_t> entry;
    std::optional<std::int64_t> trip;
    const Induction* induction_of(int reg) const {
        for (const Induction& i : inductions)
            if (i.reg == reg) return &i;
        return nullptr;
    }
};

// The bytes memory op x touches over the whole loop, [lo, hi), when its base is a known constant
// at entry stepped only by its induction and the trip count is known; nullopt otherwise.
std::optional<std::pair<std::int64_t, std::int64_t>> extent(const Graph& g, int x) {
    const Node& a = g.nodes[static_cast<std::size_t>(x)];
    const auto start = g.entry.find(a.base);
    if (start == g.entry.end() || !g.trip) return std::nullopt;
    const Induction* ind = g.induction_of(a.base);
    for (int k = 0; k < static_cast<int>(g.nodes.size()); ++k)
        if (!ind || k != ind->op)
            for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(k)].instr))
                if (o.write && o.file == isa::RegFile::Int && o.reg == a.base) return std::nullopt;
    const std::int64_t step = ind ? ind->step : 0, after = ind && x > ind->op ? 1 : 0;
    const std::int64_t imm = static_cast<std::int32_t>(a.instr.imm);
    const std::int64_t first = start->second + step * after + imm, last = first + step * std::max<std::int64_t>(*g.trip - 1, 0);
    const std::int64_t lo = std::min(first, last), hi = std::max(first, last) + a.width;
    if (lo < 0 || hi > (std::int64_t{1} << 32)) return std::nullopt; // would wrap: no claim
    return std::pair{lo, hi};
}

// Whether memory ops x (iteration i) and y (iteration i + d) may touch the same bytes.
bool may_alias(const Graph& g, const Region& r, int x, int y, int d) {
    const Node& a = g.nodes[static_cast<std::size_t>(x)];
    const Node& b = g.nodes[static_cast<std::size_t>(y)];
    if (a.base != b.base) {
        for (auto [p, q] : r.noalias)
            if ((p == a.base && q == b.base) || (p == b.base && q == a.base)) return false;
        if (g.trip && *g.trip == 0) return false;
        const auto ex = extent(g, x), ey = extent(g, y); // e.g. two arrays at known labels, a known count
        return !(ex && ey && (ex->second <= ey->first || ey->second <= ex->first));
    }
    const Induction* ind = g.induction_of(a.base);
    if (!ind) {
        // A base the loop writes other than by an induction step (a virtual register is renamed
        // every iteration; a physical one may be loaded or computed): its value in another
        // iteration is unknown, and in this one it is the same only when no write of it lies
        // between the two ops (an op reads before its own write lands).
        std::vector<int> writers;
        for (int k = 0; k < static_cast<int>(g.nodes.size()); ++k)
            for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(k)].instr))
                if (o.write && o.file == isa::RegFile::Int && o.reg == a.base) writers.push_back(k);
        if (!writers.empty()) {
            if (d > 0) return true;
            const int lo = std::min(x, y), hi = std::max(x, y);
            if (std::any_of(writers.begin(), writers.end(), [&](int w) { return lo <= w && w < hi; })) return true;
        }
    }
    // Same base, not stepped: the same addresses every iteration.
    const std::int64_t step = ind ? ind->step : 0;
    auto addr = [&](int op, const Node& n, int iter) {
        const bool after = ind && op > ind->op; // the op sees the base after this iteration's step
        return step * (iter + (after ? 1 : 0)) + static_cast<std::int64_t>(static_cast<std::int32_t>(n.instr.imm));
    };
    const std::int64_t ax = addr(x, a, 0), ay = addr(y, b, d);
    return ax < ay + b.width && ay < ax + a.width;
}

// Whether op i of a while loop has an effect a discarded iteration must not have: a store, a
// FIFO word, a load whose base is not declared `.speculate` (it could fault past the end), or a
// write of a physical register other than an induction (the exit path corrects inductions).
bool side_effect(const Graph& g, int i, const std::function<bool(int, isa::RegFile, int)>& is_virtual) {
    const Node& nd = g.nodes[static_cast<std::size_t>(i)];
    const isa::Kind k = nd.instr.info().kind;
    if (k == isa::Kind::Store || k == isa::Kind::Send || k == isa::Kind::Recv) return true;
    if (k == isa::Kind::Load && !nd.speculative) return true;
    for (const isa::RegOperand& o : isa::register_operands(nd.instr))
        if (o.write && !is_virtual(i, o.file, o.reg) && !(o.file == isa::RegFile::Int && g.induction_of(o.reg))) return true;
    return false;
}

// Speculation that is safe by construction: no side effect issues before every earlier exit test
// has been decided. Iteration i's exit test precedes the side effects of iteration i + 1 (and so
// of every later one), and those of iteration i written after the test. One bundle later: the
// ops in the bundle of a taken branch still execute.
void add_exit_edges(Graph& g, const Region& r, const std::function<bool(int, isa::RegFile, int)>& is_virtual) {
    for (int i = 0; i < static_cast<int>(g.nodes.size()); ++i) {
        if (i == r.exit_op || !side_effect(g, i, is_virtual)) continue;
        g.edges.push_back({r.exit_op, i, 1, 1, "exit before a later side effect"});
        if (i > r.exit_op) g.edges.push_back({r.exit_op, i, 1, 0, "exit before a side effect after it"});
    }
    // A value the exit path hands out (.carry, .liveout) has landed when the exit is taken: the
    // exiting iteration's when it is written before the test, else the previous iteration's.
    auto landed = [&](const std::string& name) {
        const int def = r.virtuals[static_cast<std::size_t>(r.virtual_index.at(name))].def;
        g.edges.push_back({def, r.exit_op, g.nodes[static_cast<std::size_t>(def)].latency, def < r.exit_op ? 0 : 1,
                           "live out " + name});
    };
    for (const auto& c : r.carry) landed(c.first);
    for (const auto& l : r.liveout) landed(l.first);
}

Graph build_graph(const Region& r, const std::vector<isa::Instr>& instrs, const isa::Machine& m,
                  const std::vector<OpVirtuals>& op_virtuals, const std::map<int, std::int64_t>& entry = {}) {
    Graph g;
    g.entry = entry;
    if (!r.is_while)
        if (const auto t = entry.find(r.trip_reg); t != entry.end()) g.trip = t->second;
    const int n = static_cast<int>(instrs.size());
    for (int i = 0; i < n; ++i) {
        Node nd;
        nd.instr = instrs[static_cast<std::size_t>(i)];
        const isa::OpInfo& info = nd.instr.info();
        nd.latency = static_cast<int>(m.latency_of(info));
        nd.mem = info.kind == isa::Kind::Load || info.kind == isa::Kind::Store;
        nd.store = info.kind == isa::Kind::Store;
        nd.width = info.mem_bytes ? info.mem_bytes : 4;
        if (nd.mem) nd.base = nd.instr.rs1;
        g.nodes.push_back(nd);
    }
    // The virtual an operand register of op i stands for (placeholders may be shared by virtuals
    // whose lifetimes do not meet, never within one op), or -1 for a physical register.
    auto virtual_of = [&](int i, isa::RegFile f, int reg) {
        const OpVirtuals& ov = op_virtuals[static_cast<std::size_t>(i)];
        const auto v = ov.find({static_cast<int>(f), reg});
        return v == ov.end() ? -1 : v->second;
    };
    auto is_virtual = [&](int i, isa::RegFile f, int reg) { return virtual_of(i, f, reg) >= 0; };
    for (int i = 0; i < n; ++i) {
        Node& nd = g.nodes[static_cast<std::size_t>(i)];
        if (nd.instr.info().kind != isa::Kind::Load) continue;
        const int v = virtual_of(i, isa::RegFile::Int, nd.base);
        nd.speculative = v >= 0 ? r.speculate_virtual.count(r.virtuals[static_cast<std::size_t>(v)].name) != 0
                                : r.speculate.count(nd.base) != 0;
    }
    // Induction registers: a physical integer register whose one write is `addi r, r, C`.
    std::map<int, std::vector<int>> int_defs;
    for (int i = 0; i < n; ++i)
        for (const isa::RegOperand& o : isa::register_operands(g.nodes[static_cast<std::size_t>(i)].instr))
            if (o.write && o.file == isa::RegFile::Int && !is_virtual(i, o.file, o.reg)) int_defs[o.reg].push_back(i);
    for (auto& [reg, defs] : int_defs) {
        const isa::Instr& in = g.nodes[static_cast<std::size_t>(defs[0])].instr;
        if (defs.size() == 1 && in.info().mnemonic == "addi" && in.rd == in.rs1 && reg != r.trip_reg)
            g.inductions.push_back({reg, defs[0], static_cast<std::int32_t>(in.imm)});
    }
    for (Node& nd : g.nodes)
        if (nd.mem && g.induction_of(nd.base)) nd.adjusted = true;

    // Register dependences, per register: every read depends on the write it sees (this
    // iteration's or the previous one's), must issue no later than the next write (the exposed
    // pipeline: no read of an old value once a newer write is in flight), and writes land in order.
    struct Access {
        int op;
        bool write;
    };
    // Keyed (file, register, virtual or -1): in register order, and placeholders shared by
    // virtuals (placeholder_registers) apart.
    using Key = std::tuple<int, int, int>;
    auto key_of = [&](int i, const isa::RegOperand& o) { return Key{static_cast<int>(o.file), o.reg, virtual_of(i, o.file, o.reg)}; };
    std::map<Key, std::vector<Access>> by_reg;
    for (int i = 0; i < n; ++i) {
        const Node& nd = g.nodes[static_cast<std::size_t>(i)];
        const isa::RegOperands ops = isa::register_operands(nd.instr);
        for (const isa::RegOperand& o : ops) // reads first: an op reads before its own write lands
            if (!o.write && !(nd.adjusted && o.base)) // only the base: a data operand keeps its edges
                by_reg[key_of(i, o)].push_back({i, false});
        for (const isa::RegOperand& o : ops)
            if (o.write) by_reg[key_of(i, o)].push_back({i, true});
    }
    for (const auto& [key, acc] : by_reg) {
        const auto [file, reg, v] = key;
        const bool virt = v >= 0;
        const std::string name = virt ? r.virtuals[static_cast<std::size_t>(v)].name : reg_name(static_cast<isa::RegFile>(file), reg);
        std::vector<int> writes;
        for (const Access& a : acc)
            if (a.write) writes.push_back(a.op);
        if (writes.empty()) continue; // read-only in the loop: live in, no constraint
        const int nw = static_cast<int>(writes.size());
        auto lat = [&](int op) { return g.nodes[static_cast<std::size_t>(op)].latency; };
        for (std::size_t ai = 0; ai < acc.size(); ++ai) {
            const Access& a = acc[ai];
            if (a.write) continue;
            // The write it sees: the last write before it in body order, else the last of the
            // previous iteration.
            int seen = -1, dist = 0;
            for (std::size_t k = 0; k < ai; ++k)
                if (acc[k].write) seen = acc[k].op;
            if (seen < 0) seen = writes.back(), dist = 1;
            if (!(seen == a.op && dist == 0)) g.edges.push_back({seen, a.op, lat(seen), dist, "true " + name});
            if (virt) continue; // renamed: its old value is never overwritten too early
            // The next write after it: must not issue before this read.
            int next = -1, ndist = 0;
            for (std::size_t k = ai + 1; k < acc.size(); ++k)
                if (acc[k].write) {
                    next = acc[k].op;
                    break;
                }
            if (next < 0) next = writes.front(), ndist = 1;
            if (next != a.op || ndist != 0) g.edges.push_back({a.op, next, 0, ndist, "anti " + name});
        }
        if (!virt)
            for (int k = 0; k < nw; ++k) { // output: writes land in program order
                const int from = writes[static_cast<std::size_t>(k)];
                const int to = writes[static_cast<std::size_t>((k + 1) % nw)];
                const int dist = k + 1 == nw ? 1 : 0;
                if (from == to && dist == 1 && nw == 1) continue; // one write per iteration lands in order
                // Landing after is not enough: the next write must also issue after (the
                // assembler and the checked ISS order writes by issue, so a longer write hoisted
                // above a dead shorter one would be the earlier write and land last).
                g.edges.push_back({from, to, std::max(lat(from) - lat(to) + 1, 1), dist, "output " + name});
            }
    }
    // Memory: between a store and any other access that may touch the same bytes, in both
    // directions and at every distance up to kMaxDistance; one bundle apart at least.
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y) {
            const Node& a = g.nodes[static_cast<std::size_t>(x)];
            const Node& b = g.nodes[static_cast<std::size_t>(y)];
            if (!a.mem || !b.mem || (!a.store && !b.store)) continue;
            for (int d = x < y ? 0 : 1; d <= kMaxDistance; ++d)
                if (may_alias(g, r, x, y, d)) {
                    std::string why = a.store ? (b.store ? "memory output" : "memory true") : "memory anti";
                    if (a.base != b.base) why += fmt::format(", bases r{} and r{} may alias", a.base, b.base);
                    g.edges.push_back({x, y, 1, d, why});
                    break; // the smallest distance binds most
                }
        }
    // FIFO words of one channel keep their order.
    std::map<std::uint32_t, std::vector<int>> fifo;
    for (int i = 0; i < n; ++i) {
        const isa::Kind k = g.nodes[static_cast<std::size_t>(i)].instr.info().kind;
        if (k == isa::Kind::Recv || k == isa::Kind::Send)
            fifo[g.nodes[static_cast<std::size_t>(i)].instr.imm * 2 + (k == isa::Kind::Send)].push_back(i);
    }
    for (const auto& [ch, ops] : fifo)
        for (std::size_t k = 0; k < ops.size(); ++k) {
            const bool wrap = k + 1 == ops.size();
            if (wrap && ops.size() == 1) {
                g.edges.push_back({ops[k], ops[k], 1, 1, "fifo order"});
                continue;
            }
            g.edges.push_back({ops[k], ops[(k + 1) % ops.size()], 1, wrap ? 1 : 0, "fifo order"});
        }
    if (r.is_while) add_exit_edges(g, r, is_virtual);
    return g;
}

// ---- bounds (ResMII is bounds.hpp; the RecMII over this graph stays here) ----------------------

std::vector<DepEdge> dep_edges(const Graph& g) {
    std::vector<DepEdge> d;
    for (const Edge& e : g.edges) d.push_back({e.from, e.to, e.latency, e.distance});
    return d;
}
// The values the virtual and physical registers carry from op to op (the true edges, one value
// per writer and register), for stage scheduling.
std::vector<StageValue> stage_values(const Graph& g) {
    std::map<std::pair<int, std::string>, StageValue> by;
    for (const Edge& e : g.edges) {
        if (e.why.rfind("true ", 0) != 0) continue;
        StageValue& v = by[{e.from, e.why}];
        v.def = e.from;
        v.latency = g.nodes[static_cast<std::size_t>(e.from)].latency;
        v.uses.emplace_back(e.to, e.distance);
    }
    std::vector<StageValue> out;
    for (auto& [key, v] : by) out.push_back(std::move(v));
    return out;
}

bool feasible_ii(const Graph& g, int ii) { return ii_feasible(static_cast<int>(g.nodes.size()), dep_edges(g), ii); }
int rec_mii(const Graph& g) { return recurrence_mii(static_cast<int>(g.nodes.size()), dep_edges(g)); }

// The circuit that sets the RecMII, op by op with each edge's latency and why it is there, e.g.
// "flw (line 11) -[2: true %x]-> fmul (line 12) ... : 9 cycles over 1 iteration"; "" when no
// circuit binds above 1.
// The edges (indices into g.edges) of a circuit that sets the RecMII `rec`; none when rec <= 1.
std::vector<int> critical_edges(const Graph& g, int rec) {
    if (rec <= 1) return {};
    return positive_circuit(static_cast<int>(g.nodes.size()), dep_edges(g), rec - 1);
}

std::string critical_circuit(const Graph& g, const Region& r, const std::vector<int>& circuit) {
    if (circuit.empty()) return "";
    std::string out;
    int latency = 0, distance = 0;
    for (int k : circuit) {
        const Edge& e = g.edges[static_cast<std::size_t>(k)];
        const SrcOp& op = r.ops[static_cast<std::size_t>(e.from)];
        out += fmt::format("{} (line {}) -[{}: {}]-> ", op.mnemonic, op.line, e.latency, e.why);
        latency += e.latency;
        distance += e.distance;
    }
    const SrcOp& first = r.ops[static_cast<std::size_t>(g.edges[static_cast<std::size_t>(circuit.front())].from)];
    return out + fmt::format("{} (line {}): {} cycles over {} iteration{}", first.mnemonic, first.line, latency, distance,
                             distance == 1 ? "" : "s");
}

// When the RecMII's circuit runs through memory edges between two base registers that may alias
// (no `.noalias` for them), what declaring them apart would give: "`.noalias r1, r2` (if the
// arrays never overlap) removes it: RecMII 1"; "" otherwise.
std::string alias_hint(const Graph& g, const std::vector<int>& circuit) {
    std::set<std::pair<int, int>> pairs;
    auto apart = [](const Edge& e) { return e.why.find(" may alias") != std::string::npos; };
    for (int k : circuit) {
        const Edge& e = g.edges[static_cast<std::size_t>(k)];
        if (!apart(e)) continue;
        const int a = g.nodes[static_cast<std::size_t>(e.from)].base, b = g.nodes[static_cast<std::size_t>(e.to)].base;
        pairs.insert({std::min(a, b), std::max(a, b)});
    }
    if (pairs.empty()) return "";
    const std::vector<DepEdge> edges = dep_edges(g);
    std::vector<DepEdge> kept; // every edge but the memory ones between those bases
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
        const Edge& e = g.edges[k];
        const int a = g.nodes[static_cast<std::size_t>(e.from)].base, b = g.nodes[static_cast<std::size_t>(e.to)].base;
        if (!(apart(e) && pairs.count({std::min(a, b), std::max(a, b)}))) kept.push_back(edges[k]);
    }
    std::vector<std::string> lines;
    for (auto [a, b] : pairs) lines.push_back(fmt::format(".noalias r{}, r{}", a, b));
    return fmt::format("the circuit's memory edge{} may alias: `{}` (if those arrays never overlap) give{} RecMII {}",
                       pairs.size() == 1 ? "" : "s", fmt::join(lines, "` and `"), pairs.size() == 1 ? "s" : "",
                       recurrence_mii(static_cast<int>(g.nodes.size()), kept));
}

// ---- modulo scheduling ------------------------------------------------------------------------

// The registers of file `f` op x writes.
int writes_to(const isa::Instr& x, int f) {
    int c = 0;
    for (const isa::RegOperand& o : isa::register_operands(x))
        if (o.write && static_cast<int>(o.file) == f) ++c;
    return c;
}

// Around the kernel's back edge a taken-branch bubble of b cycles delays the next pass, so the
// writes still in flight from the last pass land b cycles earlier against the new pass's than
// modulo II: a write landing at row + latency (from the pass start) meets, at cycle T, this
// pass's writes landing at T (T >= land, T - land a multiple of II) and the last pass's at
// land - b - T a positive multiple of II. Checked at the cycles `in` (at `row`) lands in either
// way, against the ops of `rows` (each with its `ops`); with few kernel copies some of these
// instances do not exist (conservative).
template <class Rows>
bool back_edge_ok(const isa::Machine& m, int ii, const Rows& rows, const isa::Instr& in, int row) {
    const int b = static_cast<int>(m.branch_penalty);
    if (b == 0) return true;
    const int land_in = row + static_cast<int>(m.latency_of(in.info()));
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        const int w_in = writes_to(in, f);
        if (w_in == 0) continue;
        std::vector<std::pair<int, int>> lands{{land_in, w_in}}; // (land, writes) of every writer of f
        int last = land_in;
        for (int r = 0; r < ii; ++r)
            for (const isa::Instr& other : rows[static_cast<std::size_t>(r)].ops)
                if (const int w = writes_to(other, f); w > 0) {
                    lands.push_back({r + static_cast<int>(m.latency_of(other.info())), w});
                    last = std::max(last, lands.back().first);
                }
        auto meet_ok = [&](int at) {
            int own = 0, old = 0;
            for (const auto& [land, w] : lands) {
                if (at >= land && (at - land) % ii == 0) own += w;
                else if (land - b - at >= ii && (land - b - at) % ii == 0) old += w;
            }
            return own == 0 || static_cast<std::uint32_t>(own + old) <= m.regs[static_cast<std::size_t>(f)].write_ports;
        };
        for (int at = land_in; at < last; at += ii)
            if (!meet_ok(at)) return false;
        for (int at = land_in - b - ii; at >= 0; at -= ii)
            if (!meet_ok(at)) return false;
    }
    return true;
}

// Each op's longest path at this II (latency - distance x II per edge, self edges left out): out
// of it to any op (`out`, its height) or into it from any op (its depth). n + 1 rounds at most:
// the fixed point when the II admits the recurrences.
std::vector<int> longest_paths(const Graph& g, int ii, bool out) {
    const int n = static_cast<int>(g.nodes.size());
    std::vector<int> len(static_cast<std::size_t>(n), 0);
    for (int iter = 0; iter < n + 1; ++iter) {
        bool changed = false;
        for (const Edge& e : g.edges) {
            if (e.from == e.to) continue;
            const std::size_t near = static_cast<std::size_t>(out ? e.from : e.to), far = static_cast<std::size_t>(out ? e.to : e.from);
            const int l = len[far] + e.latency - e.distance * ii;
            if (l > len[near]) {
                len[near] = l;
                changed = true;
            }
        }
        if (!changed) break;
    }
    return len;
}

struct Schedule {
    int ii = 0;
    std::vector<int> time;          // issue cycle of each node in the flat schedule (iteration 0)
    isa::Instr branch, counter;     // loop control in the kernel: counter decrement and branch
    int counter_row = 0;
    bool loop_control = true;       // false for a while loop: its exit test, in the last row, is the branch

    // Shifts every time by whole stages so the earliest op issues in cycle 0 of its stage 0.
    void normalise() {
        const int lo = *std::min_element(time.begin(), time.end());
        const int shift = lo >= 0 ? -(lo / ii) * ii : ((-lo + ii - 1) / ii) * ii;
        for (int& t : time) t += shift;
    }
};

class ModuloScheduler {
  public:
    // attempt 0 orders ops by height alone; later attempts break ties (and near-ties) at random.
    // `stages` > 0: only schedules of at most that many stages (every op issues before cycle
    // stages * II, and early enough for the longest path after it to end there too).
    ModuloScheduler(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter,
                    int attempt = 0, int exit_node = -1, int stages = 0)
        : g_(g), m_(m), ii_(ii), branch_(branch), counter_(counter), attempt_(attempt), exit_(exit_node),
          limit_(stages > 0 ? stages * ii - 1 : -1) {}

    std::optional<Schedule> run() {
        const int n = static_cast<int>(g_.nodes.size());
        rows_.assign(static_cast<std::size_t>(ii_), {});
        // Loop control first: the branch ends the kernel; the counter decrement anywhere. A while
        // loop has neither: its exit test is pinned to the last row (fits).
        int counter_row = -1;
        if (exit_ < 0) {
            if (!place_fixed(branch_, ii_ - 1)) return std::nullopt;
            for (int row = 0; row < ii_ && counter_row < 0; ++row)
                if (place_fixed(counter_, row)) counter_row = row;
            if (counter_row < 0) return std::nullopt;
        }
        heights();
        latest_.assign(static_cast<std::size_t>(n), std::numeric_limits<int>::max());
        if (limit_ >= 0)
            for (int i = 0; i < n; ++i) { // the longest path after an op must end by the limit too
                latest_[static_cast<std::size_t>(i)] = limit_ - std::max(0, height_[static_cast<std::size_t>(i)]);
                if (latest_[static_cast<std::size_t>(i)] < 0) return std::nullopt;
            }
        if (attempt_ >= kAttemptsPerII) { // critical ops first: the least slack, then the greatest height
            const std::vector<int> slack = slacks();
            std::mt19937 rng(static_cast<unsigned>(attempt_));
            for (std::size_t i = 0; i < height_.size(); ++i)
                height_[i] = (100000 - slack[i]) * 4096 + height_[i] * 4 + (attempt_ > kAttemptsPerII ? static_cast<int>(rng() % 6) : 0);
        } else if (attempt_ > 0) { // perturb: a random order among ops of similar height
            std::mt19937 rng(static_cast<unsigned>(attempt_));
            for (int& h : height_) h = h * 4 + static_cast<int>(rng() % 6);
        }
        time_.assign(static_cast<std::size_t>(n), -1);
        last_time_.assign(static_cast<std::size_t>(n), -1);
        // Under a stage limit a shorter search: as many stages are found as with the full budget
        // (bench_sched's while loops), at a third of the time when none exists.
        int budget = std::max(200, n * (limit_ >= 0 ? 10 : 40));
        while (budget-- > 0) {
            int op = -1;
            for (int i = 0; i < n; ++i)
                if (time_[static_cast<std::size_t>(i)] < 0 &&
                    (op < 0 || height_[static_cast<std::size_t>(i)] > height_[static_cast<std::size_t>(op)]))
                    op = i;
            if (op < 0) break;
            int estart = 0;
            for (const Edge& e : g_.edges)
                if (e.to == op && time_[static_cast<std::size_t>(e.from)] >= 0 && e.from != op)
                    estart = std::max(estart, time_[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii_);
            const int latest = latest_[static_cast<std::size_t>(op)];
            if (estart > latest) return std::nullopt;
            int chosen = -1;
            for (int t = estart; t < estart + ii_ && t <= latest && chosen < 0; ++t)
                if (fits(op, t)) chosen = t;
            if (chosen < 0) { // displace: take the first cycle it has not had yet, evict what conflicts
                const int prev = last_time_[static_cast<std::size_t>(op)];
                chosen = prev < estart ? estart : prev + 1;
                if (op == exit_) chosen += ((ii_ - 1 - chosen) % ii_ + ii_) % ii_; // its row, not earlier
                if (chosen > latest) { // past the stage limit: from the earliest again
                    chosen = estart;
                    if (op == exit_) chosen += ((ii_ - 1 - chosen) % ii_ + ii_) % ii_;
                    if (chosen > latest) return std::nullopt;
                }
                evict_for(op, chosen);
                if (!fits(op, chosen)) return std::nullopt;
            }
            place(op, chosen);
            for (const Edge& e : g_.edges) // successors now too early
                if (e.from == op && e.to != op && time_[static_cast<std::size_t>(e.to)] >= 0 &&
                    chosen + e.latency - e.distance * ii_ > time_[static_cast<std::size_t>(e.to)])
                    unplace(e.to);
        }
        for (int i = 0; i < n; ++i)
            if (time_[static_cast<std::size_t>(i)] < 0) return std::nullopt;
        for (const Edge& e : g_.edges) // self edges and the final state
            if (time_[static_cast<std::size_t>(e.from)] + e.latency - e.distance * ii_ > time_[static_cast<std::size_t>(e.to)])
                return std::nullopt;
        Schedule s;
        s.ii = ii_;
        s.time = time_;
        s.normalise();
        s.branch = branch_;
        s.counter = counter_;
        s.counter_row = counter_row;
        s.loop_control = exit_ < 0;
        return s;
    }

  private:
    struct Row {
        std::vector<isa::Instr> ops;
        std::vector<int> nodes; // -1 for loop control
    };

    bool legal(std::vector<isa::Instr> ops) const {
        std::vector<int> pinned(ops.size(), -1);
        if (!isa::assign_slots(m_, ops, pinned)) return false;
        return isa::check_bundle(m_, ops).empty();
    }

    // Writes landing in each cycle (mod II) per register file, across rows, within the ports; no
    // read of an induction register while its step is in flight.
    bool landings_ok(const isa::Instr& in, int row) const {
        const int land = (row + static_cast<int>(m_.latency_of(in.info()))) % ii_;
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            int count = writes_to(in, f);
            if (count == 0) continue;
            for (int r = 0; r < ii_; ++r)
                for (const isa::Instr& other : rows_[static_cast<std::size_t>(r)].ops)
                    if ((r + static_cast<int>(m_.latency_of(other.info()))) % ii_ == land) count += writes_to(other, f);
            if (static_cast<std::uint32_t>(count) > m_.regs[static_cast<std::size_t>(f)].write_ports) return false;
        }
        return back_edge_ok(m_, ii_, rows_, in, row);
    }

    bool induction_ok(int op, int t) const {
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        for (const Induction& ind : g_.inductions) {
            const int lat = g_.nodes[static_cast<std::size_t>(ind.op)].latency;
            if (lat <= 1) continue;
            const bool reads = nd.adjusted && nd.base == ind.reg;
            if (op == ind.op) { // its own step: no adjusted read may fall inside its flight
                for (int i = 0; i < static_cast<int>(g_.nodes.size()); ++i) {
                    const Node& o = g_.nodes[static_cast<std::size_t>(i)];
                    if (!(o.adjusted && o.base == ind.reg) || time_[static_cast<std::size_t>(i)] < 0) continue;
                    const int d = ((time_[static_cast<std::size_t>(i)] - t) % ii_ + ii_) % ii_;
                    if (d > 0 && d < lat) return false;
                }
                if (lat > ii_) return false;
            } else if (reads && time_[static_cast<std::size_t>(ind.op)] >= 0) {
                const int d = ((t - time_[static_cast<std::size_t>(ind.op)]) % ii_ + ii_) % ii_;
                if (d > 0 && d < lat) return false;
            }
        }
        return true;
    }

    bool fits(int op, int t) const {
        const int row = ((t % ii_) + ii_) % ii_;
        if (op == exit_ && row != ii_ - 1) return false;
        const isa::Instr& in = g_.nodes[static_cast<std::size_t>(op)].instr;
        std::vector<isa::Instr> ops = rows_[static_cast<std::size_t>(row)].ops;
        ops.push_back(in);
        return legal(ops) && landings_ok(in, row) && induction_ok(op, t);
    }

    bool place_fixed(const isa::Instr& in, int row) {
        std::vector<isa::Instr> ops = rows_[static_cast<std::size_t>(row)].ops;
        ops.push_back(in);
        if (!legal(ops) || !landings_ok(in, row)) return false;
        rows_[static_cast<std::size_t>(row)].ops.push_back(in);
        rows_[static_cast<std::size_t>(row)].nodes.push_back(-1);
        return true;
    }

    void place(int op, int t) {
        const int row = ((t % ii_) + ii_) % ii_;
        rows_[static_cast<std::size_t>(row)].ops.push_back(g_.nodes[static_cast<std::size_t>(op)].instr);
        rows_[static_cast<std::size_t>(row)].nodes.push_back(op);
        time_[static_cast<std::size_t>(op)] = t;
        last_time_[static_cast<std::size_t>(op)] = t;
    }

    void unplace(int op) {
        const int t = time_[static_cast<std::size_t>(op)];
        if (t < 0) return;
        Row& r = rows_[static_cast<std::size_t>(((t % ii_) + ii_) % ii_)];
        for (std::size_t k = 0; k < r.nodes.size(); ++k)
            if (r.nodes[k] == op) {
                r.nodes.erase(r.nodes.begin() + static_cast<std::ptrdiff_t>(k));
                r.ops.erase(r.ops.begin() + static_cast<std::ptrdiff_t>(k));
                break;
            }
        time_[static_cast<std::size_t>(op)] = -1;
    }

    // Evicts what keeps `op` from t: ops of its row (most recently placed first) while the bundle
    // is illegal, then ops whose writes land in its landing cycle on a file it writes, then any.
    void evict_for(int op, int t) {
        const int row = ((t % ii_) + ii_) % ii_;
        const isa::Instr& in = g_.nodes[static_cast<std::size_t>(op)].instr;
        const int land = (row + static_cast<int>(m_.latency_of(in.info()))) % ii_;
        auto writes = [](const isa::Instr& x, int f) {
            for (const isa::RegOperand& o : isa::register_operands(x))
                if (o.write && static_cast<int>(o.file) == f) return true;
            return false;
        };
        for (int guard = 0; guard < 64 && !fits(op, t); ++guard) {
            int victim = -1;
            const Row& r = rows_[static_cast<std::size_t>(row)];
            std::vector<isa::Instr> ops = r.ops;
            ops.push_back(in);
            if (!legal(ops)) {
                for (std::size_t k = r.nodes.size(); k-- > 0;)
                    if (r.nodes[k] >= 0) {
                        victim = r.nodes[k];
                        break;
                    }
            } else if (!landings_ok(in, row)) {
                for (int i = 0; i < static_cast<int>(g_.nodes.size()) && victim < 0; ++i) {
                    const int ti = time_[static_cast<std::size_t>(i)];
                    if (ti < 0 || i == op) continue;
                    const isa::Instr& x = g_.nodes[static_cast<std::size_t>(i)].instr;
                    if ((((ti % ii_) + ii_) % ii_ + static_cast<int>(m_.latency_of(x.info()))) % ii_ != land) continue;
                    for (int f = 0; f < isa::kNumRegFiles && victim < 0; ++f)
                        if (writes(in, f) && writes(x, f)) victim = i;
                }
            }
            if (victim < 0) // the row holds only loop control, or the landing is taken by it: evict any
                for (int i = 0; i < static_cast<int>(g_.nodes.size()) && victim < 0; ++i)
                    if (time_[static_cast<std::size_t>(i)] >= 0 && i != op) victim = i;
            if (victim < 0) return;
            unplace(victim);
        }
    }

    // Each op's slack: the critical path (issue to issue) less the longest paths into it and out
    // of it, at this II; 0 on a critical path.
    std::vector<int> slacks() const {
        const std::vector<int> depth = longest_paths(g_, ii_, false);
        int cp = 0;
        for (std::size_t i = 0; i < depth.size(); ++i) cp = std::max(cp, depth[i] + height_[i]);
        std::vector<int> slack(depth.size());
        for (std::size_t i = 0; i < depth.size(); ++i) slack[i] = cp - depth[i] - height_[i];
        return slack;
    }

    void heights() { height_ = longest_paths(g_, ii_, true); }

    const Graph& g_;
    const isa::Machine& m_;
    int ii_;
    isa::Instr branch_, counter_;
    int attempt_ = 0;
    int exit_ = -1; // a while loop's exit test: only in the last row
    int limit_ = -1; // the last cycle an op may issue in (a stage limit), or none
    std::vector<Row> rows_;
    std::vector<int> time_, last_time_, height_, latest_;
};

// ---- exact modulo scheduling (--exact) ---------------------------------------------------------

// Branch and bound over modulo reservation tables at one II. Every op, and the counter decrement,
// gets a row (cycle mod II); the branch is fixed at row II - 1, where the emitter puts it. A
// partial assignment is cut as soon as
//   - a row's bundle is illegal (isa::assign_slots, isa::check_bundle: adding ops never makes a
//     bundle legal again),
//   - the writes landing in one cycle mod II exceed a file's write ports,
//   - an adjusted access of an induction register falls inside the flight of its step, or
//   - the dependences among the ops placed have no stage numbers: with t = row + II * stage, an
//     edge (latency L, distance D) asks stage_to - stage_from >= ceil((row_from + L - row_to) / II)
//     - D, difference constraints that have an integer solution exactly when their graph has no
//     positive cycle (Bellman-Ford).
// These are the rules ModuloScheduler::fits and the final edge check apply, so a complete
// assignment is a modulo schedule of this tool's kernel shape (loop control in the kernel, the
// branch in its last row), and exhausting the tree proves that none exists at this II. On a
// machine with a taken-branch bubble a stage lasts II cycles in the prologue and epilogue and
// II + bubble around the kernel's back edge; `bubble` adds landings and edges under that stage
// length too (the heuristic leaves them to the assembler's check). Those rules are exact for a
// kernel that is not unrolled, but an unrolled kernel crosses its back edge once per unroll, so
// they only guide the search to tables that assemble, and a proof is a search without them. Ops go in order of height (longest path to the end), rows from the earliest
// the placed predecessors allow.
class ExactScheduler {
  public:
    enum class Outcome { Accepted, Exhausted, Timeout };
    using Clock = std::chrono::steady_clock;

    // bubble: also the rules of a stage that lasts II + the taken-branch bubble (see above).
    ExactScheduler(const Graph& g, const isa::Machine& m, int ii, const isa::Instr& branch, const isa::Instr& counter,
                   Clock::time_point deadline, bool bubble)
        : g_(g), m_(m), ii_(ii), branch_(branch), counter_(counter), deadline_(deadline), bubble_(bubble) {}

    // Calls accept for each schedule found until it returns true (Accepted), the tree is
    // exhausted, or the deadline passes.
    Outcome run(const std::function<bool(const Schedule&)>& accept) {
        accept_ = &accept;
        const int n = static_cast<int>(g_.nodes.size());
        rows_.assign(static_cast<std::size_t>(ii_), {});
        row_.assign(static_cast<std::size_t>(n), -1);
        stage_.assign(static_cast<std::size_t>(n), 0);
        if (!add(branch_, ii_ - 1, -1)) return Outcome::Exhausted;
        const std::vector<int> height = longest_paths(g_, ii_, true);
        order_.resize(static_cast<std::size_t>(n));
        std::iota(order_.begin(), order_.end(), 0);
        std::stable_sort(order_.begin(), order_.end(),
                         [&](int a, int b) { return height[static_cast<std::size_t>(a)] > height[static_cast<std::size_t>(b)]; });
        // The counter decrement has no edges: its row is tried last, at each leaf.
        const bool accepted = search(0);
        if (accepted) return Outcome::Accepted;
        return timed_out_ ? Outcome::Timeout : Outcome::Exhausted;
    }

    std::uint64_t nodes() const { return nodes_; }
    std::uint64_t tables() const { return tables_; } // complete modulo schedules handed to accept

  private:
    struct Row {
        std::vector<isa::Instr> ops;
        std::vector<int> nodes; // -1 for loop control
    };

    bool legal(const std::vector<isa::Instr>& ops) const {
        std::vector<isa::Instr> copy = ops;
        std::vector<int> pinned(copy.size(), -1);
        if (!isa::assign_slots(m_, copy, pinned)) return false;
        return isa::check_bundle(m_, copy).empty();
    }

    // Writes landing in one cycle, per file, within the ports: mod II (prologue, epilogue and
    // the kernel's copies, no taken branch) and, with the bubble's rules, around the kernel's
    // back edge (back_edge_ok).
    bool landings_ok(const isa::Instr& in, int row) const {
        const int land = (row + static_cast<int>(m_.latency_of(in.info()))) % ii_;
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            int count = writes_to(in, f);
            if (count == 0) continue;
            for (int r = 0; r < ii_; ++r)
                for (const isa::Instr& other : rows_[static_cast<std::size_t>(r)].ops)
                    if ((r + static_cast<int>(m_.latency_of(other.info()))) % ii_ == land) count += writes_to(other, f);
            if (static_cast<std::uint32_t>(count) > m_.regs[static_cast<std::size_t>(f)].write_ports) return false;
        }
        return !bubble_ || back_edge_ok(m_, ii_, rows_, in, row);
    }

    // Cycles from one stage to the next: II in straight-line code, II + the taken-branch bubble
    // around the kernel's back edge. A rule in real cycles must hold for both.
    std::vector<int> periods() const {
        if (m_.branch_penalty == 0 || !bubble_) return {ii_};
        return {ii_, ii_ + static_cast<int>(m_.branch_penalty)};
    }

    bool induction_ok(int op, int row) const {
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        for (const Induction& ind : g_.inductions) {
            const int lat = g_.nodes[static_cast<std::size_t>(ind.op)].latency;
            if (lat <= 1) continue;
            if (op == ind.op) {
                if (lat > ii_) return false;
                for (int i = 0; i < static_cast<int>(g_.nodes.size()); ++i) {
                    const Node& o = g_.nodes[static_cast<std::size_t>(i)];
                    if (!(o.adjusted && o.base == ind.reg) || row_[static_cast<std::size_t>(i)] < 0) continue;
                    const int d = ((row_[static_cast<std::size_t>(i)] - row) % ii_ + ii_) % ii_;
                    if (d > 0 && d < lat) return false;
                }
            } else if (nd.adjusted && nd.base == ind.reg && row_[static_cast<std::size_t>(ind.op)] >= 0) {
                const int d = ((row - row_[static_cast<std::size_t>(ind.op)]) % ii_ + ii_) % ii_;
                if (d > 0 && d < lat) return false;
            }
        }
        return true;
    }

    bool add(const isa::Instr& in, int row, int node) {
        Row& r = rows_[static_cast<std::size_t>(row)];
        std::vector<isa::Instr> ops = r.ops;
        ops.push_back(in);
        if (!legal(ops) || !landings_ok(in, row)) return false;
        r.ops.push_back(in);
        r.nodes.push_back(node);
        return true;
    }

    void remove_last(int row) {
        Row& r = rows_[static_cast<std::size_t>(row)];
        r.ops.pop_back();
        r.nodes.pop_back();
    }

    static int ceil_div(int a, int b) { return a >= 0 ? (a + b - 1) / b : -((-a) / b); }

    // Stage numbers for the placed ops (longest paths from 0), or false on a positive cycle.
    bool stages() {
        const int n = static_cast<int>(g_.nodes.size());
        for (int i = 0; i < n; ++i) stage_[static_cast<std::size_t>(i)] = 0;
        for (int iter = 0; iter <= n; ++iter) {
            bool changed = false;
            for (const Edge& e : g_.edges) {
                const int rf = row_[static_cast<std::size_t>(e.from)], rt = row_[static_cast<std::size_t>(e.to)];
                if (rf < 0 || rt < 0) continue;
                int w = ceil_div(rf + e.latency - rt, ii_); // stages apart, at least, for each period
                for (const int period : periods()) w = std::max(w, ceil_div(rf + e.latency - rt, period));
                w -= e.distance;
                if (e.from == e.to) {
                    if (w > 0) return false;
                    continue;
                }
                if (stage_[static_cast<std::size_t>(e.from)] + w > stage_[static_cast<std::size_t>(e.to)]) {
                    stage_[static_cast<std::size_t>(e.to)] = stage_[static_cast<std::size_t>(e.from)] + w;
                    changed = true;
                }
            }
            if (!changed) return true;
        }
        return false;
    }

    bool leaf() {
        for (int row = 0; row < ii_; ++row) {
            // A table's check assembles the file (milliseconds, not a node's microseconds): the
            // clock is read before each, or a run of leaves overran the budget tenfold.
            if (Clock::now() >= deadline_) timed_out_ = true;
            if (timed_out_) return false;
            if (!add(counter_, row, -1)) continue;
            Schedule s;
            s.ii = ii_;
            const int n = static_cast<int>(g_.nodes.size());
            s.time.resize(static_cast<std::size_t>(n));
            for (int i = 0; i < n; ++i)
                s.time[static_cast<std::size_t>(i)] = row_[static_cast<std::size_t>(i)] + ii_ * stage_[static_cast<std::size_t>(i)];
            s.normalise();
            s.branch = branch_;
            s.counter = counter_;
            s.counter_row = row;
            ++tables_;
            const bool ok = (*accept_)(s);
            remove_last(row);
            if (ok) return true;
        }
        return false;
    }

    bool search(std::size_t k) {
        if ((++nodes_ & 255) == 1 && Clock::now() >= deadline_) timed_out_ = true; // the first node too
        if (timed_out_) return false;
        if (k == order_.size()) return leaf();
        const int op = order_[k];
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        // Rows from the earliest the placed predecessors allow (short stages first).
        int start = 0;
        for (const Edge& e : g_.edges)
            if (e.to == op && e.from != op && row_[static_cast<std::size_t>(e.from)] >= 0)
                start = std::max(start, row_[static_cast<std::size_t>(e.from)] + ii_ * stage_[static_cast<std::size_t>(e.from)] +
                                            e.latency - e.distance * ii_);
        for (int j = 0; j < ii_; ++j) {
            const int row = ((start + j) % ii_ + ii_) % ii_;
            if (!induction_ok(op, row)) continue;
            row_[static_cast<std::size_t>(op)] = row;
            if (add(nd.instr, row, op)) {
                const std::vector<int> saved = stage_;
                if (stages() && search(k + 1)) return true;
                stage_ = saved;
                remove_last(row);
            }
            row_[static_cast<std::size_t>(op)] = -1;
            if (timed_out_) return false;
        }
        return false;
    }

    const Graph& g_;
    const isa::Machine& m_;
    int ii_;
    isa::Instr branch_, counter_;
    Clock::time_point deadline_;
    bool bubble_ = true;
    const std::function<bool(const Schedule&)>* accept_ = nullptr;
    std::vector<Row> rows_;
    std::vector<int> row_, stage_;
    std::vector<int> order_;
    std::uint64_t nodes_ = 0, tables_ = 0;
    bool timed_out_ = false;
};

// ---- registers --------------------------------------------------------------------------------

struct Allocation {
    int unroll = 1;
    std::vector<int> copies;                     // per virtual: registers in rotation
    std::vector<std::vector<std::string>> regs;  // per virtual, per copy
    int counter = -1;                            // integer register of the kernel counter
    std::vector<std::string> scratch;
    std::vector<int> lifetime;                   // per virtual, cycles
    int entry_nops = 0;                          // between prologue and kernel (kernel_landings_ok)
};

Allocation allocate(const Region& r, const Graph& g, const Schedule& s, const std::set<std::pair<int, int>>& named,
                    const isa::Machine& m, std::string_view file, int min_unroll = 1) {
    Allocation a;
    std::vector<int> pool[2];
    for (int f = 0; f < 2; ++f)
        for (int reg = 0; reg < static_cast<int>(m.regs[static_cast<std::size_t>(f)].count); ++reg)
            if (!named.count({f, reg})) pool[f].push_back(reg); // taken from the top down
    auto take = [&](isa::RegFile f, const std::string& what) {
        auto& p = pool[static_cast<int>(f)];
        if (p.empty())
            throw RegisterPressure(base::SourceLoc(file, static_cast<int>(r.begin + 1)),
                 fmt::format("register pressure: no free {} register left for {} ({} has {} per file, the source names "
                             "{}, the tool has taken the other {} for the kernel's register copies)",
                             isa::kRegFileNames[static_cast<std::size_t>(f)], what, m.name,
                             m.regs[static_cast<std::size_t>(f)].count,
                             std::count_if(named.begin(), named.end(), [&](auto& x) { return x.first == static_cast<int>(f); }),
                             std::count_if(a.scratch.begin(), a.scratch.end(),
                                           [&](const std::string& x) { return x[0] == file_prefix(f); })));
        const int reg = p.back();
        p.pop_back();
        a.scratch.push_back(reg_name(f, reg));
        return reg;
    };
    if (!r.is_while) a.counter = take(isa::RegFile::Int, "the kernel counter");
    // Lifetimes: from the def's issue to the last read (a new value may be issued in the cycle of
    // the last read of the old one, the exposed pipeline's rule).
    int need = 1;
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int def = r.virtuals[v].def;
        int last = s.time[static_cast<std::size_t>(def)] + g.nodes[static_cast<std::size_t>(def)].latency;
        for (const Edge& e : g.edges)
            if (e.from == def && e.why.rfind("true ", 0) == 0 && e.why.substr(5) == r.virtuals[v].name)
                last = std::max(last, s.time[static_cast<std::size_t>(e.to)] + e.distance * s.ii);
        if (r.is_while) { // a value the exit path reads must outlive the exit test that may hand it out
            const std::string& name = r.virtuals[v].name;
            const auto c = r.carry.find(name);
            const bool now = r.liveout.count(name) || (c != r.carry.end() && def < r.exit_op);
            const bool next = c != r.carry.end() && (def > r.exit_op || !c->second.old.empty());
            const int tb = s.time[static_cast<std::size_t>(r.exit_op)];
            if (now) last = std::max(last, tb + 1);
            if (next) last = std::max(last, tb + s.ii + 1);
        }
        const int life = last - s.time[static_cast<std::size_t>(def)];
        a.lifetime.push_back(life);
        const int k = std::max(1, (life + s.ii - 1) / s.ii);
        a.copies.push_back(static_cast<int>(std::bit_ceil(static_cast<unsigned>(k))));
        need = std::max(need, a.copies.back());
    }
    a.unroll = std::max(need, min_unroll);
    // A while loop pays the taken-branch bubble once per kernel pass: more kernel copies (the same
    // registers rotating, a power of two) until it is at most a twentieth of the pass. No remainder
    // to run and no register more; only more code and exit paths.
    if (r.is_while)
        while (a.unroll < kMaxBubbleUnroll && 20 * static_cast<int>(m.branch_penalty) > s.ii * a.unroll) a.unroll *= 2;
    const std::vector<int> pool0[2] = {pool[0], pool[1]};
    const std::vector<std::string> scratch0 = a.scratch;
    try { // a register set of its own for every virtual, while there are enough
        for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
            std::vector<std::string> regs;
            for (int c = 0; c < a.copies[v]; ++c)
                regs.push_back(reg_name(r.virtuals[v].file, take(r.virtuals[v].file, r.virtuals[v].name)));
            a.regs.push_back(regs);
        }
        return a;
    } catch (const RegisterPressure&) {
        pool[0] = pool0[0], pool[1] = pool0[1];
        a.scratch = scratch0;
        a.regs.clear();
    }
    // Else virtuals share registers where their lifetimes do not meet. In the kernel (unroll x II
    // cycles, a circle) copy c of v holds the instances of the iterations k = c mod copies, each
    // from its def's issue to its last read (the next owner may issue in that cycle); the prologue,
    // epilogue and exit paths hold subsets of those instances. Carried values and live-outs keep
    // registers of their own: the value before the loop and after its exit live longer than any
    // instance in the kernel.
    const int circle = a.unroll * s.ii;
    std::vector<std::vector<char>> busy[2];   // per file, per register taken: cycles occupied
    std::vector<int> busy_reg[2];             // the register of each
    a.regs.assign(r.virtuals.size(), {});
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const Virtual& x = r.virtuals[v];
        const int f = static_cast<int>(x.file);
        const bool own = r.carry.count(x.name) || r.liveout.count(x.name);
        const int t0 = s.time[static_cast<std::size_t>(x.def)];
        for (int c = 0; c < a.copies[v]; ++c) {
            std::vector<char> need(static_cast<std::size_t>(circle), 0);
            for (int k = c; k < a.unroll; k += a.copies[v])
                for (int t = 0; t < a.lifetime[v]; ++t)
                    need[static_cast<std::size_t>(((t0 + k * s.ii + t) % circle + circle) % circle)] = 1;
            int slot = -1;
            for (std::size_t b = 0; !own && slot < 0 && b < busy[f].size(); ++b) {
                if (busy[f][b].empty()) continue; // a register of its own
                bool free = true;
                for (int t = 0; free && t < circle; ++t) free = !(need[static_cast<std::size_t>(t)] && busy[f][b][static_cast<std::size_t>(t)]);
                if (free) slot = static_cast<int>(b);
            }
            if (slot < 0) {
                busy_reg[f].push_back(take(x.file, x.name));
                busy[f].push_back(own ? std::vector<char>{} : std::vector<char>(static_cast<std::size_t>(circle), 0));
                slot = static_cast<int>(busy[f].size()) - 1;
            }
            if (!own)
                for (int t = 0; t < circle; ++t) busy[f][static_cast<std::size_t>(slot)][static_cast<std::size_t>(t)] |= need[static_cast<std::size_t>(t)];
            a.regs[v].push_back(reg_name(x.file, busy_reg[f][static_cast<std::size_t>(slot)]));
        }
    }
    return a;
}

// Whether the kernel, `unroll` copies of the II rows, passes the assembler's write-port check
// when entered both ways: from the prologue (straight, or after `entry_nops` as long as the
// taken-branch bubble) and around its back edge (after the bubble). The reservation table
// counts landings modulo II, which is exact only without a bubble. The assembler checks each
// write against the writes in flight where it is issued, merging the paths into a bundle, so a
// write of the kernel meets those of both ways in; with entry nops both bring the same writes
// (the same registers: the kernel's copies rotate with the prologue's passes) at the same cycles.
// Costs nothing beside assembling the file.
bool kernel_landings_ok(const Graph& g, const Schedule& s, int unroll, const isa::Machine& m, bool entry_nops) {
    if (m.branch_penalty == 0) return true;
    const int pass = unroll * s.ii, bubble = static_cast<int>(m.branch_penalty);
    int last_stage = 0, longest = 1;
    for (int t : s.time) last_stage = std::max(last_stage, t / s.ii);
    for (const Node& nd : g.nodes) longest = std::max(longest, nd.latency);
    longest = std::max(longest, static_cast<int>(m.latency_of(s.counter.info())));
    // Per cycle of a pass (and beyond its end): writes issued in it, writes in flight into it.
    using Count = std::array<std::uint32_t, isa::kNumRegFiles>;
    std::vector<Count> own(static_cast<std::size_t>(pass + longest)), in(own.size());
    auto add = [](Count& c, const isa::Instr& x) {
        for (const isa::RegOperand& o : isa::register_operands(x))
            if (o.write) ++c[static_cast<std::size_t>(o.file)];
    };
    auto issue = [&](const isa::Instr& x, int at, bool in_prologue) {
        const int lands = at + static_cast<int>(m.latency_of(x.info()));
        add(own[static_cast<std::size_t>(lands)], x);
        if (lands < pass) return;
        if (lands - pass - bubble >= 0) add(in[static_cast<std::size_t>(lands - pass - bubble)], x); // around the back edge
        if (in_prologue && !entry_nops) add(in[static_cast<std::size_t>(lands - pass)], x);      // from the prologue
    };
    for (int c = 0; c < unroll; ++c)
        for (std::size_t i = 0; i < g.nodes.size(); ++i)
            issue(g.nodes[i].instr, c * s.ii + s.time[i] % s.ii, s.time[i] / s.ii < last_stage);
    if (s.loop_control) issue(s.counter, (unroll - 1) * s.ii + s.counter_row, false);
    for (std::size_t y = 0; y < own.size(); ++y)
        for (int f = 0; f < isa::kNumRegFiles; ++f) {
            const std::size_t k = static_cast<std::size_t>(f);
            if (own[y][k] > 0 && own[y][k] + in[y][k] > m.regs[k].write_ports) return false;
        }
    return true;
}

// ---- emission -----------------------------------------------------------------------------------

// An iteration index in the emitted code: `base` is 0 (prologue, absolute) or the trip count N
// (epilogue, relative); the kernel's instances are steady.
struct Iter {
    bool from_end = false;
    int offset = 0;
};

class Emitter {
  public:
    Emitter(const Region& r, const Graph& g, const Schedule& s, const Allocation& a, const isa::Machine& m)
        : r_(r), g_(g), s_(s), a_(a), m_(m) {
        stages_ = 1;
        for (int t : s.time) stages_ = std::max(stages_, t / s.ii + 1);
    }
    int stages() const { return stages_; }

    // Memory op `op` on an induction register (nullopt for any other op): the induction op,
    // whether `op` follows it in the body, and m = floor((t_op - t_ind - latency) / II) + 1, the
    // later iterations' increments that have landed when `op` issues.
    struct InductionView {
        const Induction* ind;
        int after, m;
    };
    std::optional<InductionView> induction_view(int op) const {
        const Node& nd = g_.nodes[static_cast<std::size_t>(op)];
        if (!nd.adjusted) return std::nullopt;
        const Induction& ind = *g_.induction_of(nd.base);
        const int ta = s_.time[static_cast<std::size_t>(ind.op)], la = g_.nodes[static_cast<std::size_t>(ind.op)].latency;
        const int diff = s_.time[static_cast<std::size_t>(op)] - ta - la;
        const int m = (diff >= 0 ? diff / s_.ii : -((-diff + s_.ii - 1) / s_.ii)) + 1; // floor + 1
        return InductionView{&ind, op > ind.op ? 1 : 0, m};
    }

    // Offset change of memory op `op` of iteration `it` on an induction register: the increments
    // the op should see minus those that have landed when it issues.
    std::int64_t delta(int op, std::optional<Iter> it) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        const Induction& ind = *view->ind;
        const int after = view->after, m = view->m;
        std::int64_t seen_minus_i; // (increments landed) - i
        if (!it) seen_minus_i = m;  // steady state
        else if (!it->from_end) seen_minus_i = std::max(it->offset + m, 0) - it->offset;
        else seen_minus_i = std::min(m, -it->offset); // i = N + offset, at most N increments
        return ind.step * (after - seen_minus_i);
    }

    // Offset change of memory op `op` in an iteration run alone at the schedule's times: its
    // own induction step has landed when the op issues after it (m >= 1), no other.
    std::int64_t delta_alone(int op) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        return view->ind->step * (view->after - (view->m >= 1 ? 1 : 0));
    }

    std::string instance(int op, int iteration_mod, std::optional<Iter> it) const {
        std::vector<std::string> vreg;
        for (std::size_t v = 0; v < r_.virtuals.size(); ++v) {
            const int k = a_.copies[v];
            vreg.push_back(a_.regs[v][static_cast<std::size_t>(((iteration_mod % k) + k) % k)]);
        }
        return op_text(r_.ops[static_cast<std::size_t>(op)], r_, vreg, delta(op, it));
    }

    static std::string bundle(const std::vector<std::string>& ops) {
        if (ops.empty()) return "        nop\n";
        if (ops.size() == 1) return "        " + ops[0] + "\n";
        std::string s = "        { ";
        for (std::size_t k = 0; k < ops.size(); ++k) s += (k ? " ; " : "") + ops[k];
        return s + " }\n";
    }

    // `trip_min` (.trip, 0: none) drops the paths no run can take; `shape` receives the bundles
    // of each part (whole_run_cycles).
    std::string code(const std::string& trip, const std::string& uid, int trip_min = 0, CountedShape* shape = nullptr) const {
        const int ii = s_.ii, p = stages_ - 1, u = a_.unroll;
        const std::string rk = reg_name(isa::RegFile::Int, a_.counter);
        const int alu_lat = static_cast<int>(m_.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
        auto nops = [&](int n) {
            std::string s;
            for (int k = 0; k < n; ++k) s += "        nop\n";
            return s;
        };
        const int min_trip = p + u;
        CountedShape sh;
        sh.alu_latency = std::max(1, alu_lat);
        sh.penalty = static_cast<int>(m_.branch_penalty);
        sh.guard = trip_min < 1;
        sh.short_path = trip_min < min_trip;
        sh.prologue_passes = p, sh.unroll = u, sh.ii = ii, sh.entry_nops = a_.entry_nops;
        std::string o;
        // Sequential copy: trip counts below the pipeline's minimum, and the unroll remainder.
        if (sh.guard) o += fmt::format("        beqz {}, {}_done\n", trip, uid);
        if (sh.sequential_copy()) {
            o += fmt::format("{}_check:\n", uid);
            if (sh.short_path) {
                o += fmt::format("        slti {}, {}, {}\n", rk, trip, min_trip) + nops(alu_lat - 1);
                o += fmt::format("        bnez {}, {}_seq\n", rk, uid);
            }
            if (u > 1) {
                o += fmt::format("        addi {}, {}, {}\n", rk, trip, -p) + nops(alu_lat - 1);
                o += fmt::format("        andi {}, {}, {}\n", rk, rk, u - 1) + nops(alu_lat - 1);
                o += fmt::format("        beqz {}, {}_pipe\n", rk, uid);
            } else {
                o += fmt::format("        jmp {}_pipe\n", uid);
            }
            o += fmt::format("{}_seq:\n", uid);
            std::vector<std::string> vreg0;
            for (std::size_t v = 0; v < r_.virtuals.size(); ++v) vreg0.push_back(a_.regs[v][0]);
            // One iteration alone: each op after the previous one's result has landed, or, with
            // .trip (the default's code stays as it was), the modulo schedule's own placement of
            // one iteration when that is shorter: each bundle a subset of a kernel row (slots,
            // ports and landings hold), every dependence within the iteration met by the schedule,
            // and every result landed before the next iteration starts.
            int serial = 0, first = s_.time[0], flat = 0;
            for (std::size_t k = 0; k < r_.ops.size(); ++k) {
                serial += std::max(1, g_.nodes[k].latency);
                first = std::min(first, s_.time[k]);
                flat = std::max(flat, s_.time[k] + std::max(1, g_.nodes[k].latency));
            }
            flat -= first;
            if (trip_min > 0 && flat < serial) {
                for (int t = first; t < first + flat; ++t) {
                    std::vector<std::string> ops;
                    for (std::size_t k = 0; k < r_.ops.size(); ++k)
                        if (s_.time[k] == t) ops.push_back(op_text(r_.ops[k], r_, vreg0, delta_alone(static_cast<int>(k))));
                    o += bundle(ops);
                }
                sh.body = flat;
            } else {
                for (std::size_t k = 0; k < r_.ops.size(); ++k) {
                    o += "        " + op_text(r_.ops[k], r_, vreg0, 0) + "\n";
                    o += nops(g_.nodes[k].latency - 1);
                }
                sh.body = serial;
            }
            o += fmt::format("        addi {}, {}, -1\n", trip, trip) + nops(alu_lat - 1);
            o += fmt::format("        bnez {}, {}_check\n", trip, uid);
            if (sh.short_path) o += fmt::format("        jmp {}_done\n", uid); // else the count never reaches 0 here
        }
        // Pipelined: N >= P + U and (N - P) % U == 0; the counter holds the kernel passes.
        o += fmt::format("{}_pipe:\n", uid);
        const int lag = lag_passes(alu_lat);
        o += fmt::format("        addi {}, {}, {}\n", rk, trip, -p) + nops(alu_lat - 1);
        if (u > 1) o += fmt::format("        srli {}, {}, {}\n", rk, rk, std::countr_zero(static_cast<unsigned>(u))) + nops(alu_lat - 1);
        if (lag > 0) o += fmt::format("        addi {}, {}, {}\n", rk, rk, -lag) + nops(alu_lat - 1);
        sh.setup = sh.alu_latency * (1 + (u > 1 ? 1 : 0) + (lag > 0 ? 1 : 0));
        o += fmt::format("# prologue: {} pass{} of {} cycles\n", p, p == 1 ? "" : "es", ii);
        for (int pass = 0; pass < p; ++pass)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii;
                    if (t % ii == row && st <= pass) ops.push_back(instance(static_cast<int>(op), pass - st, Iter{false, pass - st}));
                }
                o += bundle(ops);
            }
        o += fmt::format("# kernel: {} cop{} of II = {} cycles, {} stage{}\n", u, u == 1 ? "y" : "ies", ii, stages_,
                         stages_ == 1 ? "" : "s");
        for (int k = 0; k < a_.entry_nops; ++k) o += "        nop\n";
        o += fmt::format("{}_kernel:\n", uid);
        for (int c = 0; c < u; ++c)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii;
                    if (t % ii == row) ops.push_back(instance(static_cast<int>(op), p + c - st, std::nullopt));
                }
                if (c == u - 1 && row == s_.counter_row) ops.push_back(fmt::format("addi {}, {}, -1", rk, rk));
                if (c == u - 1 && row == ii - 1) ops.push_back(fmt::format("bnez {}, {}_kernel", rk, uid));
                o += bundle(ops);
            }
        o += fmt::format("# epilogue: {} pass{}\n", p, p == 1 ? "" : "es");
        std::string epilogue;
        for (int q = 0; q < p; ++q)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii;
                    if (t % ii == row && st >= q + 1)
                        ops.push_back(instance(static_cast<int>(op), p + q - st, Iter{true, q - st}));
                }
                epilogue += bundle(ops);
            }
        while (epilogue.size() >= 12 && epilogue.compare(epilogue.size() - 12, 12, "        nop\n") == 0)
            epilogue.resize(epilogue.size() - 12); // trailing empty bundles: the drain below covers them
        o += epilogue;
        // Results still in flight land before the code after the loop runs; the trip register
        // ends at 0 as in the sequential meaning.
        int drain = 0;
        for (const Node& nd : g_.nodes) drain = std::max(drain, nd.latency - 1);
        o += nops(drain);
        o += fmt::format("        li {}, 0\n", trip);
        o += fmt::format("{}_done:\n", uid);
        sh.tail = static_cast<int>(std::count(epilogue.begin(), epilogue.end(), '\n')) + drain + 1; // a bundle a line
        if (shape) *shape = sh;
        return o;
    }

    // ---- while loops: exits from the prologue and from every kernel copy ----

    // The branch's stage, and the increments of induction `ind` the loop has issued by the time
    // the exit of iteration e is taken, beyond the e + a of the sequential meaning (a: the step
    // comes before the exit test in the source). Later iterations' steps run ahead of the exit.
    int exit_stage() const { return s_.time[static_cast<std::size_t>(r_.exit_op)] / s_.ii; }
    int ahead(const Induction& ind) const {
        const int a = ind.op < r_.exit_op ? 1 : 0;
        return std::max(0, exit_stage() - s_.time[static_cast<std::size_t>(ind.op)] / s_.ii + 1 - a);
    }

    // Offset change of memory op `op` of iteration i (absolute: i counts from the first
    // iteration, else relative to the kernel); `exiting`: after the exit of that iteration, when
    // no step beyond those already issued and the sequential ones is issued.
    std::int64_t delta_while(int op, int i, bool absolute, std::optional<int> exiting) const {
        const auto view = induction_view(op);
        if (!view) return 0;
        const Induction& ind = *view->ind;
        const int after = view->after, m = view->m;
        std::int64_t seen = i + m;                                                         // increments landed
        if (absolute) seen = std::max<std::int64_t>(seen, 0);
        if (exiting) seen = std::min<std::int64_t>(seen, *exiting + (ind.op < r_.exit_op ? 1 : 0) + ahead(ind));
        return ind.step * (after - (seen - i));
    }

    // The registers of iteration i's virtuals (a carried one's copy rotates like any other).
    std::vector<std::string> regs_of(int i) const {
        std::vector<std::string> vreg;
        for (std::size_t v = 0; v < r_.virtuals.size(); ++v) {
            const int k = a_.copies[v];
            vreg.push_back(a_.regs[v][static_cast<std::size_t>(((i % k) + k) % k)]);
        }
        return vreg;
    }
    std::string reg_of(const std::string& name, int i) const {
        return regs_of(i)[static_cast<std::size_t>(r_.virtual_index.at(name))];
    }

    std::string instance_at(int op, int i, std::int64_t delta) const {
        const std::vector<std::string> prev = regs_of(i - 1);
        return op_text(r_.ops[static_cast<std::size_t>(op)], r_, regs_of(i), delta, &prev, op);
    }

    // A register copy in one op: `addi d, s, 0` or `fmov d, s`, and its latency.
    std::pair<std::string, int> move(const std::string& to, const std::string& from) const {
        const bool f = from[0] == 'f';
        return {f ? fmt::format("fmov {}, {}", to, from) : fmt::format("addi {}, {}, 0", to, from),
                static_cast<int>(m_.latency[static_cast<std::size_t>(f ? isa::OpClass::FAdd : isa::OpClass::Alu)])};
    }
    // The operation of a move's text, for the slot and port checks.
    static isa::Instr move_instr(const std::string& text) {
        const auto regs = split_operands(text.substr(text.find(' ')));
        isa::RegFile f;
        int d = 0, src = 0;
        parse_reg(regs[0], f, d);
        parse_reg(regs[1], f, src);
        isa::Instr in;
        in.opcode = f == isa::RegFile::Float ? isa::opcode("fmov") : isa::opcode("addi");
        in.rd = static_cast<std::uint8_t>(d);
        in.rs1 = static_cast<std::uint8_t>(src);
        return in;
    }
    // The moves packed into as few bundles as the machine takes (isa::assign_slots and
    // isa::check_bundle decide), then nops until they have landed.
    std::string moves_text(const std::vector<std::pair<std::string, int>>& ms) const {
        std::string o;
        int lat = 1;
        std::vector<std::vector<isa::Instr>> ops; // per bundle: each move goes to the first that takes it
        std::vector<std::vector<std::string>> texts;
        for (const auto& [text, l] : ms) {
            lat = std::max(lat, l);
            const isa::Instr in = move_instr(text);
            std::size_t b = 0;
            for (; b < ops.size(); ++b) {
                std::vector<isa::Instr> trial = ops[b];
                trial.push_back(in);
                std::vector<int> pinned(trial.size(), -1);
                if (isa::assign_slots(m_, trial, pinned) && isa::check_bundle(m_, trial).empty()) break;
            }
            if (b == ops.size()) ops.emplace_back(), texts.emplace_back();
            ops[b].push_back(in);
            texts[b].push_back(text);
        }
        for (const auto& t : texts) o += bundle(t);
        for (int k = 1; k < lat && !ms.empty(); ++k) o += "        nop\n";
        return o;
    }

    // The exit path's first bundles: carried and live-out values of the exiting iteration e
    // (landed, by the graph's edges) to their registers.
    std::vector<std::pair<std::string, int>> exit_moves(int e) const {
        std::vector<std::pair<std::string, int>> ms;
        for (const auto& [name, c] : r_.carry) {
            const int def = r_.virtuals[static_cast<std::size_t>(r_.virtual_index.at(name))].def;
            ms.push_back(move(c.out, reg_of(name, def < r_.exit_op ? e : e - 1)));
            if (!c.old.empty()) ms.push_back(move(c.old, reg_of(name, e - 1)));
        }
        for (const auto& [name, reg] : r_.liveout) ms.push_back(move(reg, reg_of(name, e)));
        return ms;
    }

    // The exit test of iteration i, branching to `label`; inverted, it is the kernel's back edge.
    std::string exit_branch(int i, const std::string& label, bool invert) const {
        static const std::map<std::string, std::string> inverse = {{"beqz", "bnez"}, {"bnez", "beqz"}, {"beq", "bne"},
                                                                   {"bne", "beq"},   {"blt", "bge"},   {"bge", "blt"},
                                                                   {"bltu", "bgeu"}, {"bgeu", "bltu"}};
        SrcOp b = r_.ops[static_cast<std::size_t>(r_.exit_op)];
        if (invert) b.mnemonic = inverse.at(b.mnemonic);
        b.operands.back() = label;
        const std::vector<std::string> prev = regs_of(i - 1);
        return op_text(b, r_, regs_of(i), 0, &prev, r_.exit_op);
    }

    // Writes per register file landing in each cycle after the exit test of pass `pass` (cycle 0)
    // from the ops issued before it: the passes back to the prologue's first (`absolute`: an exit
    // in the prologue), or in the kernel the copies of this pass and, a taken-branch bubble
    // earlier or not (the prologue before), all earlier ones.
    using Landings = std::vector<std::array<std::uint32_t, isa::kNumRegFiles>>;
    Landings in_flight(int pass, bool absolute, int horizon) const {
        Landings at(static_cast<std::size_t>(horizon));
        const int b = static_cast<int>(m_.branch_penalty), p = stages_ - 1, copy = absolute ? pass : pass - p;
        for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
            const Node& nd = g_.nodes[i];
            const int st = s_.time[i] / s_.ii;
            for (int j = 0;; ++j) { // j passes back
                const int issue = s_.time[i] % s_.ii - (s_.ii - 1) - j * s_.ii;
                if (issue + nd.latency <= 0 || (absolute && (j > pass || st > pass - j))) break;
                // Before this pass's first copy: the previous kernel pass, a bubble earlier, or the
                // prologue (its pass p - (j - copy), holding stages up to that; entered after
                // entry nops as long as the bubble, or straight).
                const bool before_kernel = !absolute && j > copy;
                const bool from_prologue = before_kernel && st <= p - (j - copy);
                // Shifts by which the write lands earlier: none within this pass; before it, the
                // back edge's bubble, and none from a prologue entered straight.
                const bool straight = !before_kernel || (from_prologue && a_.entry_nops == 0 && b > 0);
                for (const int shift : {before_kernel ? b : 0, 0}) {
                    if (const int land = issue - shift + nd.latency; land > 0 && land < horizon)
                        add_writes(at[static_cast<std::size_t>(land)], nd.instr, 1);
                    if (!straight || !before_kernel) break;
                }
            }
        }
        return at;
    }
    static void add_writes(std::array<std::uint32_t, isa::kNumRegFiles>& at, const isa::Instr& in, int sign) {
        for (const isa::RegOperand& o : isa::register_operands(in))
            if (o.write) at[static_cast<std::size_t>(o.file)] += static_cast<std::uint32_t>(sign);
    }
    bool room(const std::array<std::uint32_t, isa::kNumRegFiles>& at) const {
        for (int f = 0; f < isa::kNumRegFiles; ++f)
            if (at[static_cast<std::size_t>(f)] > m_.regs[static_cast<std::size_t>(f)].write_ports) return false;
        return true;
    }

    // What runs after the exit of iteration e is taken at the end of pass P: the older iterations
    // complete, the exiting one runs what precedes its exit test in the source, younger ones are
    // dropped (they have issued no side effect); then in-flight results land and inductions step
    // back by what ran ahead. The exit moves go to the first bundles whose slots and whose
    // landing cycle's write ports (with the results still in flight) take them, and the
    // completing iterations start when they have landed and no write of theirs meets one in
    // flight on a port.
    std::string exit_path(int pass, int e, bool absolute, bool taken) const {
        const int ii = s_.ii;
        std::vector<std::vector<std::string>> rows;
        std::vector<std::vector<const isa::Instr*>> row_instrs;
        for (int q = pass + 1; q <= e + stages_ - 1; ++q)
            for (int row = 0; row < ii; ++row) {
                rows.emplace_back();
                row_instrs.emplace_back();
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = q - st;
                    if (t % ii != row || static_cast<int>(op) == r_.exit_op || i > e || (absolute && i < 0)) continue;
                    if (i == e && static_cast<int>(op) > r_.exit_op) continue;
                    rows.back().push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, absolute, e)));
                    row_instrs.back().push_back(&g_.nodes[op].instr);
                }
            }
        while (!rows.empty() && rows.back().empty()) rows.pop_back(), row_instrs.pop_back();
        int longest = 1;
        for (const Node& nd : g_.nodes) longest = std::max(longest, nd.latency);
        const auto ms = exit_moves(e);
        const int horizon = 2 * (longest + static_cast<int>(m_.branch_penalty) + ii) + static_cast<int>(ms.size()) * 16 + 64;
        // The exit path's first bundle issues in cycle 1, or after the bubble of a taken exit.
        const int first = 1 + (taken ? static_cast<int>(m_.branch_penalty) : 0);
        Landings at = in_flight(pass, absolute, horizon);
        std::vector<std::vector<isa::Instr>> move_ops;
        std::vector<std::vector<std::string>> move_texts;
        int lat = 1;
        for (const auto& [text, l] : ms) {
            lat = std::max(lat, l);
            const isa::Instr in = move_instr(text);
            for (std::size_t b = 0;; ++b) {
                if (b == move_ops.size()) move_ops.emplace_back(), move_texts.emplace_back();
                std::vector<isa::Instr> trial = move_ops[b];
                trial.push_back(in);
                std::vector<int> pinned(trial.size(), -1);
                const std::size_t land = static_cast<std::size_t>(first) + b + static_cast<std::size_t>(l);
                auto cycle = at[std::min(land, at.size() - 1)];
                add_writes(cycle, in, 1);
                if (isa::assign_slots(m_, trial, pinned) && isa::check_bundle(m_, trial).empty() && room(cycle)) {
                    move_ops[b].push_back(in);
                    move_texts[b].push_back(text);
                    if (land < at.size()) add_writes(at[land], in, 1);
                    break;
                }
            }
        }
        std::string o;
        for (const auto& t : move_texts) o += bundle(t);
        // The completing iterations from cycle `start`: after the moves have landed, and later
        // while a write of theirs would meet one in flight on a port.
        int start = first + static_cast<int>(move_ops.size()) + (ms.empty() ? 0 : lat - 1);
        for (int tries = 0; tries < horizon / 2; ++tries, ++start) {
            Landings trial = at;
            bool fits = true;
            for (std::size_t k = 0; fits && k < row_instrs.size(); ++k)
                for (const isa::Instr* in : row_instrs[k]) {
                    const std::size_t land = static_cast<std::size_t>(start) + k + m_.latency_of(in->info());
                    if (land >= trial.size()) continue;
                    add_writes(trial[land], *in, 1);
                    fits = fits && room(trial[land]);
                }
            if (fits) break;
        }
        if (!rows.empty())
            for (int k = first + static_cast<int>(move_ops.size()); k < start; ++k) o += "        nop\n";
        for (const auto& row : rows) o += bundle(row);
        // The code after the loop may read or write any register, so it starts once every write
        // has landed (those in flight at the exit, the moves', the completing iterations'), not
        // after the longest latency of all. The inductions step back once the integer writes have
        // landed (their own steps among them) and the completing iterations have read them.
        int cycle = rows.empty() ? first + static_cast<int>(move_ops.size()) : start + static_cast<int>(rows.size());
        int last = cycle, int_last = cycle;
        auto lands = [&](int land, const isa::Instr& in) {
            last = std::max(last, land);
            if (writes_to(in, static_cast<int>(isa::RegFile::Int)) > 0) int_last = std::max(int_last, land);
        };
        for (std::size_t c = 0; c < at.size(); ++c)
            for (int f = 0; f < isa::kNumRegFiles; ++f)
                if (at[c][static_cast<std::size_t>(f)] > 0) {
                    last = std::max(last, static_cast<int>(c));
                    if (f == static_cast<int>(isa::RegFile::Int)) int_last = std::max(int_last, static_cast<int>(c));
                }
        for (std::size_t k = 0; k < row_instrs.size(); ++k)
            for (const isa::Instr* in : row_instrs[k]) lands(start + static_cast<int>(k) + static_cast<int>(m_.latency_of(in->info())), *in);
        const int alu_lat = static_cast<int>(m_.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
        bool stepped = false;
        for (const Induction& ind : g_.inductions)
            if (const int x = ahead(ind); x > 0) {
                for (; !stepped && cycle < int_last; ++cycle) o += "        nop\n";
                stepped = true;
                o += fmt::format("        addi {0}, {0}, {1}\n", reg_name(isa::RegFile::Int, ind.reg), -ind.step * x);
                last = std::max(last, cycle + alu_lat);
                ++cycle;
            }
        for (; cycle < last; ++cycle) o += "        nop\n";
        return o;
    }

    std::string while_code(const std::string& uid) const {
        const int ii = s_.ii, p = stages_ - 1, u = a_.unroll, sb = exit_stage();
        std::string o;
        struct Exit {
            std::string label;
            int pass, e;
            bool absolute;
        };
        std::vector<Exit> exits;
        std::vector<std::pair<std::string, int>> in; // carried values into the copy iteration 0 reads
        for (const auto& [name, c] : r_.carry) in.push_back(move(reg_of(name, -1), c.in));
        o += moves_text(in);
        o += fmt::format("# prologue: {} pass{} of {} cycles (exit test from pass {})\n", p, p == 1 ? "" : "es", ii, sb);
        for (int pass = 0; pass < p; ++pass)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = pass - st;
                    if (t % ii != row || st > pass) continue;
                    if (static_cast<int>(op) == r_.exit_op) {
                        exits.push_back({fmt::format("{}_exit_p{}", uid, pass), pass, i, true});
                        ops.push_back(exit_branch(i, exits.back().label, false));
                    } else {
                        ops.push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, true, std::nullopt)));
                    }
                }
                o += bundle(ops);
            }
        o += fmt::format("# kernel: {} cop{} of II = {} cycles, {} stage{}; each copy ends in the exit test\n", u,
                         u == 1 ? "y" : "ies", ii, stages_, stages_ == 1 ? "" : "s");
        for (int k = 0; k < a_.entry_nops; ++k) o += "        nop\n";
        o += fmt::format("{}_kernel:\n", uid);
        std::vector<Exit> kernel_exits;
        for (int c = 0; c < u; ++c)
            for (int row = 0; row < ii; ++row) {
                std::vector<std::string> ops;
                for (std::size_t op = 0; op < g_.nodes.size(); ++op) {
                    const int t = s_.time[op], st = t / ii, i = p + c - st;
                    if (t % ii != row) continue;
                    if (static_cast<int>(op) == r_.exit_op) {
                        const bool last = c == u - 1;
                        kernel_exits.push_back({fmt::format("{}_exit_k{}", uid, c), p + c, i, false});
                        ops.push_back(exit_branch(i, last ? uid + "_kernel" : kernel_exits.back().label, last));
                    } else {
                        ops.push_back(instance_at(static_cast<int>(op), i, delta_while(static_cast<int>(op), i, false, std::nullopt)));
                    }
                }
                o += bundle(ops);
            }
        // The last copy's exit falls through; the other exits branch to their own paths.
        std::rotate(kernel_exits.begin(), kernel_exits.end() - 1, kernel_exits.end());
        exits.insert(exits.begin(), kernel_exits.begin(), kernel_exits.end());
        for (std::size_t k = 0; k < exits.size(); ++k) {
            const Exit& x = exits[k];
            if (x.absolute)
                o += fmt::format("# exit of iteration {} at the end of prologue pass {}\n", x.e, x.pass);
            else
                o += fmt::format("# exit from kernel copy {}: its iteration in stage {} leaves{}\n", x.pass - p, sb,
                                 stages_ - 1 == sb ? "" : fmt::format(", the {} older complete", stages_ - 1 - sb));
            if (k > 0) o += x.label + ":\n";
            o += exit_path(x.pass, x.e, x.absolute, k > 0);
            if (k + 1 < exits.size()) o += fmt::format("        jmp {}_done\n", uid);
        }
        o += fmt::format("{}_done:\n", uid);
        return o;
    }

    // How many kernel passes the counter's decrement lands late for the branch that reads it.
    int lag_passes(int alu_lat) const {
        const int land = s_.counter_row + alu_lat; // cycle (from its pass's start) it lands
        return land <= s_.ii - 1 ? 0 : (land - (s_.ii - 1) + s_.ii - 1) / s_.ii;
    }

  private:
    const Region& r_;
    const Graph& g_;
    const Schedule& s_;
    const Allocation& a_;
    const isa::Machine& m_;
    int stages_ = 1;
};

// ---- the sequential meaning -------------------------------------------------------------------

std::string linear_loop(const Region& r, const std::vector<std::string>& placeholder_name, const isa::Machine& m,
                        const std::string& uid) {
    const int alu_lat = static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
    std::string o;
    o += fmt::format("        beqz {}, {}_lin_end\n", r.trip, uid);
    o += uid + "_lin:\n";
    for (const SrcOp& op : r.ops) {
        o += "        " + op_text(op, r, placeholder_name, 0) + "\n";
        for (std::uint32_t k = 1; k < m.latency_of(isa::kOps[op.opcode]); ++k) o += "        nop\n";
    }
    o += fmt::format("        addi {}, {}, -1\n", r.trip, r.trip);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    o += fmt::format("        bnez {}, {}_lin\n", r.trip, uid);
    o += uid + "_lin_end:\n";
    return o;
}

// A while loop's sequential meaning: the body up to its exit test, the test branching out, the
// rest; `count` counts the iterations that do not exit (verification reads it, never compares it).
std::string linear_while_loop(const Region& r, const std::vector<std::string>& placeholder_name, const isa::Machine& m,
                              const std::string& count, const std::string& uid) {
    const int alu_lat = static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
    auto mv = [&](const std::string& to, const std::string& from) { // one copy, landed before the next op
        const bool f = from[0] == 'f';
        std::string t = f ? fmt::format("        fmov {}, {}\n", to, from) : fmt::format("        addi {}, {}, 0\n", to, from);
        for (std::uint32_t k = 1; k < m.latency[static_cast<std::size_t>(f ? isa::OpClass::FAdd : isa::OpClass::Alu)]; ++k)
            t += "        nop\n";
        return t;
    };
    auto placeholder_of = [&](const std::string& name) {
        return placeholder_name[static_cast<std::size_t>(r.virtual_index.at(name))];
    };
    std::string o;
    for (const auto& [name, c] : r.carry) o += mv(placeholder_of(name), c.in);
    for (const auto& [name, c] : r.carry) // OLD: the value each iteration starts with
        if (!c.old.empty()) o += mv(c.old, placeholder_of(name));
    o += fmt::format("        li {}, 0\n", count);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    o += uid + "_lin:\n";
    for (std::size_t k = 0; k < r.ops.size(); ++k) {
        SrcOp op = r.ops[k];
        if (static_cast<int>(k) == r.exit_op) op.operands.back() = uid + "_lin_end";
        o += "        " + op_text(op, r, placeholder_name, 0) + "\n";
        for (std::uint32_t j = 1; j < m.latency_of(isa::kOps[op.opcode]); ++j) o += "        nop\n";
    }
    o += fmt::format("        addi {0}, {0}, 1\n", count);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    for (const auto& [name, c] : r.carry)
        if (!c.old.empty()) o += mv(c.old, placeholder_of(name));
    o += fmt::format("        jmp {}_lin\n", uid);
    o += uid + "_lin_end:\n";
    for (const auto& [name, c] : r.carry) o += mv(c.out, placeholder_of(name));
    for (const auto& [name, reg] : r.liveout) o += mv(reg, placeholder_of(name));
    return o;
}

assembler::AsmOptions asm_options(const PipelineOptions& opts = {}) {
    assembler::AsmOptions a;
    a.read_file = opts.read_file;
    return a;
}

// Integer registers that hold a known constant when bundle `at` starts, from the straight-line
// code before it back to the last label (a jump target: another way in): `li`, and `addi` of a
// known register; any other write forgets its register, a jump or call forgets them all.
// Conditional branches fall through to `at`.
std::map<int, std::int64_t> constants_at(const isa::ObjectFile& obj, const std::vector<std::vector<isa::Instr>>& bundles,
                                         std::uint32_t at) {
    std::uint32_t from = 0;
    for (const isa::Symbol& s : obj.symbols)
        if (s.kind == isa::SymbolKind::Code && s.value < at) from = std::max(from, s.value);
    std::map<int, std::int64_t> known;
    for (std::uint32_t b = from; b < at && b < bundles.size(); ++b) {
        std::map<int, std::int64_t> next = known; // a bundle reads its sources at issue
        for (const isa::Instr& in : bundles[b]) {
            const isa::OpInfo& info = in.info();
            if (info.kind == isa::Kind::Jump || info.kind == isa::Kind::JumpLink || info.kind == isa::Kind::JumpReg)
                next.clear(); // a call may change any register; after a jump only a label leads on
            for (const isa::RegOperand& o : isa::register_operands(in))
                if (o.write && o.file == isa::RegFile::Int) next.erase(o.reg);
            const std::int64_t imm = static_cast<std::int32_t>(in.imm);
            if (info.mnemonic == "li") next[in.rd] = static_cast<std::uint32_t>(imm);
            else if (info.mnemonic == "addi")
                if (const auto s = known.find(in.rs1); s != known.end())
                    next[in.rd] = static_cast<std::uint32_t>(s->second + imm);
        }
        known = std::move(next);
    }
    return known;
}

isa::ObjectFile assemble_or_fail(const std::string& text, std::string_view file, const isa::Machine& m,
                                 const std::string& what, const PipelineOptions& opts = {}) {
    const assembler::AsmResult res = assembler::assemble_string(text, file, m, asm_options(opts));
    if (!res.ok || res.warnings > 0)
        throw base::Error(base::SourceLoc(file), fmt::format("the {} does not assemble cleanly:\n{}", what, res.diagnostics));
    return res.object;
}

// Each row of the II as data: its ops with the slots they issue in (isa::assign_slots, as the
// emitter bundles them), mnemonic, class and stage; the loop control (counter, branch) in no stage.
// The report's table and the picture are both drawn from it.
std::vector<TableRow> schedule_rows(const Graph& g, const Region& r, const Schedule& s, const isa::Machine& m) {
    std::vector<TableRow> rows(static_cast<std::size_t>(s.ii));
    for (int row = 0; row < s.ii; ++row) {
        std::vector<isa::Instr> ops;
        std::vector<std::pair<std::string, int>> names; // mnemonic, stage
        for (std::size_t k = 0; k < g.nodes.size(); ++k)
            if (s.time[k] % s.ii == row) ops.push_back(g.nodes[k].instr), names.push_back({r.ops[k].mnemonic, s.time[k] / s.ii});
        if (s.loop_control && row == s.counter_row) ops.push_back(s.counter), names.push_back({"addi", -1});
        if (s.loop_control && row == s.ii - 1) ops.push_back(s.branch), names.push_back({"bnez", -1});
        std::vector<int> pinned(ops.size(), -1);
        isa::assign_slots(m, ops, pinned);
        for (std::size_t k = 0; k < ops.size(); ++k)
            rows[static_cast<std::size_t>(row)].ops.push_back(
                {m.slots[ops[k].slot].name, names[k].first,
                 std::string(isa::kOpClassNames[static_cast<std::size_t>(ops[k].info().cls)]), names[k].second});
    }
    return rows;
}

std::string mrt_text(const std::vector<TableRow>& rows) {
    std::string o = "#   modulo reservation table (cycle mod II: operations [stage])\n";
    for (std::size_t row = 0; row < rows.size(); ++row) {
        std::string cells;
        for (const TableRow::Op& op : rows[row].ops)
            cells += op.stage >= 0 ? fmt::format(" {}:{}[{}]", op.slot, op.op, op.stage)
                                   : fmt::format(" {}:{}({})", op.slot, op.op, op.op == "bnez" ? "loop" : "counter");
        o += fmt::format("#   {:>3} |{}\n", row, cells);
    }
    return o;
}

// The schedule as LoopReport draws it: each row of the II with its ops (slot, mnemonic, class,
// stage; loop control in no stage) and the register ports they use (reads at issue, writes where
// they land, mod II), and each virtual register's lifetime from its definition.
LoopReport schedule_picture(const Graph& g, const Region& r, const Schedule& s, std::vector<TableRow> rows,
                            const std::vector<int>& lifetime, const isa::Machine& m, std::string_view filename,
                            const std::string& verdict) {
    LoopReport p;
    p.label = r.is_while ? "software-pipelined while" : "software-pipelined";
    p.source = fmt::format("{}:{}", filename, r.begin + 1);
    p.machine = m.name;
    p.ii = s.ii;
    p.verdict = verdict;
    for (const isa::SlotDesc& d : m.slots) p.slots.push_back(d.name);
    for (int f = 0; f < 2; ++f) {
        p.read_ports[f] = m.regs[static_cast<std::size_t>(f)].read_ports;
        p.write_ports[f] = m.regs[static_cast<std::size_t>(f)].write_ports;
        p.file_size[f] = m.regs[static_cast<std::size_t>(f)].count;
    }
    p.table = std::move(rows);
    auto land = [&](const isa::Instr& in, int issue) { // reads at issue, writes where they land, mod II
        for (const isa::RegOperand& o : isa::register_operands(in))
            ++(o.write ? p.table[static_cast<std::size_t>((issue + static_cast<int>(m.latency_of(in.info()))) % s.ii)].writes
                       : p.table[static_cast<std::size_t>(issue % s.ii)].reads)[static_cast<int>(o.file)];
    };
    for (std::size_t k = 0; k < g.nodes.size(); ++k) land(g.nodes[k].instr, s.time[k]);
    if (s.loop_control) {
        land(s.counter, s.counter_row);
        land(s.branch, s.ii - 1);
    }
    p.ops = static_cast<int>(g.nodes.size()) + (s.loop_control ? 2 : 0);
    std::vector<int> live[2] = {std::vector<int>(static_cast<std::size_t>(s.ii), 0), std::vector<int>(static_cast<std::size_t>(s.ii), 0)};
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int born = r.virtuals[v].def >= 0 ? s.time[static_cast<std::size_t>(r.virtuals[v].def)] : 0;
        const int f = static_cast<int>(r.virtuals[v].file);
        p.lifetimes.push_back({r.virtuals[v].name, lifetime[v], born, f});
        for (int c = 0; c < std::max(1, lifetime[v]); ++c) ++live[f][static_cast<std::size_t>((born + c) % s.ii)];
    }
    for (int f = 0; f < 2; ++f) p.max_live[f] = *std::max_element(live[f].begin(), live[f].end());
    return p;
}

// The report lines of a while loop: how far iterations run ahead of the exit test, what they may
// do there, and the exit paths.
std::string while_report(const Graph& g, const Region& r, const Schedule& s, const PipelineResult& res) {
    const int tb = s.time[static_cast<std::size_t>(r.exit_op)];
    std::string o = fmt::format("#   exit test in stage {}: {} later iteration{} start{} before it is decided, with no side effect "
                                "(stores, FIFO words, loads not .speculate, physical registers but inductions wait for it)\n",
                                res.exit_stage, res.exit_stage, res.exit_stage == 1 ? "" : "s", res.exit_stage == 1 ? "s" : "");
    std::map<std::pair<bool, std::string>, int> load_ahead; // base (physical first) -> iterations past the exit its loads may run
    for (std::size_t k = 0; k < g.nodes.size(); ++k)
        if (g.nodes[k].instr.info().kind == isa::Kind::Load && g.nodes[k].speculative) {
            int ahead = tb >= s.time[k] ? (tb - s.time[k]) / s.ii : 0;
            if (static_cast<int>(k) > r.exit_op) ahead += 1; // the exiting iteration's own load after its test
            const SrcOp& op = r.ops[k];
            const std::string& mem = op.operands.back(); // `off(base)`: the name as written
            const std::string base = mem.substr(mem.find('(') + 1, mem.rfind(')') - mem.find('(') - 1);
            int& a = load_ahead[{base[0] == '%', base}];
            a = std::max(a, ahead);
        }
    for (const auto& [base, n] : load_ahead)
        o += fmt::format("#   speculative loads on {}: up to {} iteration{} past the exit (those addresses must be mapped)\n",
                         base.second, n, n == 1 ? "" : "s");
    const int prologue_exits = std::max(0, res.stages - 1 - res.exit_stage);
    o += fmt::format("#   exit paths: {} from the prologue, {} from the kernel (one per copy); no trip count, no "
                     "sequential fallback\n", prologue_exits, res.unroll);
    return o;
}

// The virtuals each op of the region names, in operand order.
std::vector<std::vector<int>> virtuals_of_ops(const Region& r) {
    static const std::regex name(R"(%[A-Za-z_][A-Za-z0-9_]*)");
    std::vector<std::vector<int>> out;
    for (const SrcOp& op : r.ops) {
        std::vector<int>& vs = out.emplace_back();
        for (const std::string& operand : op.operands)
            for (auto it = std::sregex_iterator(operand.begin(), operand.end(), name); it != std::sregex_iterator(); ++it)
                if (const auto v = r.virtual_index.find(it->str()); v != r.virtual_index.end()) vs.push_back(v->second);
    }
    return out;
}

// The placeholder register of each virtual in the sequential meaning (`uses`: virtuals_of_ops):
// a free register of its own (the highest the file does not name) while there are enough; else virtuals whose lifetimes in
// one iteration do not meet share one (a virtual read before its definition, carried or live
// out is live throughout; the op of a last read never also defines the next owner, so the
// registers of one op stand for one virtual each).
std::vector<int> placeholder_registers(const Region& r, const std::vector<std::vector<int>>& uses,
                                       const std::set<std::pair<int, int>>& named, const isa::Machine& m,
                                       std::string_view filename) {
    std::vector<std::vector<int>> free(2);
    for (int f = 0; f < 2; ++f)
        for (int reg = static_cast<int>(m.regs[static_cast<std::size_t>(f)].count) - 1; reg >= 0; --reg)
            if (!named.count({f, reg})) free[static_cast<std::size_t>(f)].push_back(reg);
    const std::size_t nv = r.virtuals.size();
    std::vector<int> out(nv, -1);
    std::array<std::size_t, 2> need{};
    for (const Virtual& v : r.virtuals) ++need[static_cast<std::size_t>(v.file)];
    if (need[0] <= free[0].size() && need[1] <= free[1].size()) { // one each, as always
        std::array<std::size_t, 2> next{};
        for (std::size_t v = 0; v < nv; ++v) {
            const auto f = static_cast<std::size_t>(r.virtuals[v].file);
            out[v] = free[f][next[f]++];
        }
        return out;
    }
    const int n = static_cast<int>(r.ops.size());
    std::vector<int> first(nv, n), last(nv, -1);
    for (int i = 0; i < n; ++i)
        for (int v : uses[static_cast<std::size_t>(i)]) {
            first[static_cast<std::size_t>(v)] = std::min(first[static_cast<std::size_t>(v)], i);
            last[static_cast<std::size_t>(v)] = std::max(last[static_cast<std::size_t>(v)], i);
        }
    for (std::size_t v = 0; v < nv; ++v) {
        const Virtual& x = r.virtuals[v];
        if (first[v] < x.def || r.carry.count(x.name) || r.liveout.count(x.name)) first[v] = -1, last[v] = n;
        else first[v] = x.def;
    }
    std::vector<std::size_t> order(nv);
    for (std::size_t v = 0; v < nv; ++v) order[v] = v;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return first[a] < first[b]; });
    std::vector<std::vector<std::pair<int, int>>> busy(2); // (last op, register)
    std::vector<std::vector<int>> pool = free;
    for (auto& p : pool) std::reverse(p.begin(), p.end()); // taken from the back: the highest first
    for (std::size_t v : order) {
        const auto f = static_cast<std::size_t>(r.virtuals[v].file);
        auto& b = busy[f];
        for (auto it = b.begin(); it != b.end();)
            if (it->first < first[v]) pool[f].push_back(it->second), it = b.erase(it);
            else ++it;
        if (pool[f].empty()) fail(filename, static_cast<int>(r.begin + 1), "too many virtual registers");
        out[v] = pool[f].back();
        pool[f].pop_back();
        b.push_back({last[v], out[v]});
    }
    return out;
}

// A region's sequential meaning: each virtual on its placeholder register (placeholder_registers),
// a while loop's iterations counted in the lowest free register.
struct Sequential {
    std::vector<std::string> placeholder_name;      // per virtual
    std::set<std::pair<int, int>> placeholders;     // (file, reg) of every placeholder
    std::vector<OpVirtuals> op_virtuals;            // per op: its operands' placeholders -> virtual
    std::string iteration_register;                 // a while loop's
    std::string loop;                               // the text
};

Sequential sequential_meaning(const Region& r, const std::set<std::pair<int, int>>& named, const isa::Machine& m,
                              std::string_view filename, const std::string& uid) {
    if (r.trip_reg >= static_cast<int>(m.regs[0].count)) fail(filename, static_cast<int>(r.begin + 1), "no such register");
    Sequential q;
    const std::vector<std::vector<int>> uses = virtuals_of_ops(r);
    const std::vector<int> regs = placeholder_registers(r, uses, named, m, filename);
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int f = static_cast<int>(r.virtuals[v].file);
        q.placeholders.insert({f, regs[v]});
        q.placeholder_name.push_back(reg_name(r.virtuals[v].file, regs[v]));
    }
    for (const std::vector<int>& vs : uses) {
        OpVirtuals& ov = q.op_virtuals.emplace_back();
        for (int v : vs) ov[{static_cast<int>(r.virtuals[static_cast<std::size_t>(v)].file), regs[static_cast<std::size_t>(v)]}] = v;
    }
    if (r.is_while) { // the lowest register neither named nor a placeholder counts iterations
        for (int reg = 1; reg < static_cast<int>(m.regs[0].count) && q.iteration_register.empty(); ++reg)
            if (!named.count({0, reg}) && !q.placeholders.count({0, reg})) q.iteration_register = reg_name(isa::RegFile::Int, reg);
        if (q.iteration_register.empty()) fail(filename, static_cast<int>(r.begin + 1), "too many virtual registers");
    }
    q.loop = r.is_while ? linear_while_loop(r, q.placeholder_name, m, q.iteration_register, uid)
                        : linear_loop(r, q.placeholder_name, m, uid);
    return q;
}

// The labels of the region with this ordinal in its file: __sa_... for the first (as with one).
std::string region_uid(int ordinal) { return ordinal == 0 ? "__sa" : fmt::format("__sa{}", ordinal); }

// Which region of a file pipeline_impl schedules, and what it may take. The file's other regions
// are written as their sequential meanings (the code around this one); `reusable` are registers
// the file names that the tool may take anyway (the scratch registers of regions already
// pipelined, live only inside them).
struct Target {
    std::size_t index = 0; // among the file's regions, in order
    int ordinal = 0;       // for its labels (region_uid)
    std::set<std::pair<int, int>> reusable;
};

struct Impl {
    PipelineResult res;
    std::string emitted; // the region's code alone
    Span span;           // its lines in the file (after `#if machine` sections are resolved)
};

// How far pipeline_impl goes: the sequential meaning between the region markers (every region
// between its own pair), the sequential meaning as a file, or the pipelined code.
enum class Upto { Markers, Linear, Pipelined };

Impl pipeline_impl(std::string_view text, std::string_view filename, const isa::Machine& m, const PipelineOptions& opts,
                   Upto upto, const Target& target = {}) {
    const bool linear_only = upto == Upto::Markers;
    const std::vector<std::string> lines = split_lines(machine_sections(text, filename, m));
    const std::vector<Span> spans = region_spans(lines, filename);
    if (target.index >= spans.size())
        fail(filename, 0, fmt::format("no region {}: the file has {} .pipeline region{}", target.index + 1, spans.size(),
                                      spans.size() == 1 ? "" : "s"));
    const Region r = parse_region(lines, filename, spans[target.index]);
    check_named_in_range(lines, filename, m);
    std::set<std::pair<int, int>> named = named_registers(lines);
    for (const auto& reg : target.reusable) named.erase(reg);

    const std::string uid = region_uid(target.ordinal);
    const Sequential q = sequential_meaning(r, named, m, filename, uid);
    // The lines [from, to) with every other region as its sequential meaning.
    auto around = [&](std::size_t from, std::size_t to) {
        std::string o;
        for (std::size_t i = from; i < to; ++i) {
            const auto other = std::find_if(spans.begin(), spans.end(), [&](const Span& sp) { return sp.first == i; });
            if (other == spans.end()) {
                o += lines[i] + "\n";
                continue;
            }
            const Region ro = parse_region(lines, filename, *other);
            const int k = static_cast<int>(other - spans.begin()) - static_cast<int>(target.index) + target.ordinal;
            const std::string seq = sequential_meaning(ro, named, m, filename, region_uid(k)).loop;
            o += linear_only ? std::string(kRegionBegin) + "\n" + seq + kRegionEnd + "\n" : seq;
            i = other->second;
        }
        return o;
    };
    const std::string before = around(0, r.begin), after = around(r.end + 1, lines.size());
    Impl impl;
    impl.span = spans[target.index];
    PipelineResult& res = impl.res;
    res.is_while = r.is_while;
    res.iteration_register = q.iteration_register;
    const std::string& loop = q.loop;
    if (linear_only) {
        res.linear = before + kRegionBegin + "\n" + loop + kRegionEnd + "\n" + after;
        return impl;
    }
    // Both files say first which machine they are for (a `# machine:` line of the source's is replaced).
    const std::string header = fmt::format("# machine: {}\n", m.reference());
    const std::string code_before = assembler::header_machine(before).empty() ? before : before.substr(before.find('\n') + 1);
    res.linear = header + code_before + loop + after;
    res.linear_region_at = header.size() + code_before.size();
    if (upto == Upto::Linear) return impl;
    const isa::ObjectFile lin = assemble_or_fail(res.linear, filename, m, "sequential meaning of the region", opts);
    const std::vector<std::vector<isa::Instr>> bundles = isa::decode_bundles(lin);
    std::uint32_t b0 = 0;
    for (const isa::Symbol& s : lin.symbols)
        if (s.name == uid + "_lin" && s.kind == isa::SymbolKind::Code) b0 = s.value;
    const std::uint32_t region_start = b0;
    std::vector<isa::Instr> instrs;
    for (const SrcOp& op : r.ops) {
        instrs.push_back(bundles[b0][0]);
        b0 += std::max<std::uint32_t>(1, m.latency_of(isa::kOps[op.opcode]));
    }
    const Graph g = build_graph(r, instrs, m, q.op_virtuals, constants_at(lin, bundles, region_start));
    // The trip count register is the loop's: the pipelined loop counts its passes in a register of
    // its own, so a value read or written there inside the region would differ from the
    // sequential meaning's, silently.
    if (!r.is_while)
        for (std::size_t k = 0; k < r.ops.size(); ++k)
            for (const isa::RegOperand& o : isa::register_operands(instrs[k]))
                if (o.file == isa::RegFile::Int && o.reg == r.trip_reg) {
                    const std::string& line = lines[static_cast<std::size_t>(r.ops[k].line - 1)];
                    std::size_t at = line.find(r.trip, line.find(r.ops[k].mnemonic) + r.ops[k].mnemonic.size());
                    while (at != std::string::npos && at + r.trip.size() < line.size() &&
                           std::isdigit(static_cast<unsigned char>(line[at + r.trip.size()])))
                        at = line.find(r.trip, at + 1); // r9, not r90
                    const std::size_t col = at == std::string::npos ? line.find_first_not_of(" \t") : at;
                    throw base::Error(base::SourceLoc(filename, r.ops[k].line, static_cast<int>(col + 1)),
                                      fmt::format("'{}' {} the trip count register {} inside the region: the pipelined "
                                                  "loop keeps its own count, so its value there is not defined (copy it "
                                                  "into another register before `.pipeline`, and step that copy)\n{}\n{}^",
                                                  r.ops[k].mnemonic, o.write ? "writes" : "reads", r.trip, line,
                                                  std::string(col, ' ')));
                }
    // Loop control in the kernel: `addi counter, counter, -1` and `bnez counter, kernel`.
    isa::Instr branch, counter;
    branch.opcode = isa::opcode("bnez");
    counter.opcode = isa::opcode("addi");
    counter.rd = counter.rs1 = 0; // register numbers do not matter for the resource checks
    res.rec_mii = rec_mii(g);
    // The loop control takes slots too; a while loop's exit test is its loop control.
    const ResBound res_bound = r.is_while ? res_mii(m, instrs) : res_mii(m, instrs, kLoopControl);
    res.res_mii = res_bound.ii();
    res.mii = std::max(res.rec_mii, res.res_mii);
    const int lo = opts.ii > 0 ? opts.ii : res.mii;
    const int hi = opts.ii > 0 ? opts.ii : res.mii + opts.max_ii_search;
    // The first II whose schedule also assembles: the kernel's taken-branch bubble (a machine's
    // branch_penalty) shifts the next pass, which the assembler's checks see and the MRT does not.
    std::optional<Schedule> sched;
    std::optional<Allocation> alloc_found;
    std::string emitted, why_not;
    int stages = 1;
    // One II: schedules in different op orders (until `deadline` when given), the first that
    // also assembles is kept.
    using Clock = std::chrono::steady_clock;
    // A schedule's code (registers allocated, text emitted), before it is assembled.
    struct Built {
        Schedule s;
        Allocation alloc;
        std::string code;
        int stages = 1;
        CountedShape shape; // a counted loop's
    };
    const TripDirective& trip = r.trip_count;
    // `first_least`: at least this many kernel copies (more amortise a taken-branch bubble).
    auto build = [&](const Schedule& s, int first_least = 1) -> std::optional<Built> {
        std::optional<Allocation> fitted;
        try {
            // More kernel copies where the taken-branch bubble makes writes meet on a port.
            for (int least = first_least; least <= kMaxPortUnroll; least *= 2) {
                fitted = allocate(r, g, s, named, m, filename, least);
                if (kernel_landings_ok(g, s, fitted->unroll, m, false)) break;
                if (kernel_landings_ok(g, s, fitted->unroll, m, true)) {
                    fitted->entry_nops = static_cast<int>(m.branch_penalty);
                    break;
                }
                if (fitted->unroll >= kMaxPortUnroll) {
                    why_not = fmt::format("II {}: writes meet on a register file's ports across the kernel's back edge "
                                          "(its {}-cycle branch bubble) with up to {} kernel copies", s.ii,
                                          m.branch_penalty, fitted->unroll);
                    return std::nullopt;
                }
                least = fitted->unroll;
            }
        } catch (const RegisterPressure& e) {
            const std::string what = e.what();
            why_not = fmt::format("II {}: {}", s.ii, what.substr(std::min(what.size(), what.find("error: ") + 7)));
            return std::nullopt;
        }
        Built b{s, std::move(*fitted), "", 1, {}};
        const Emitter em(r, g, s, b.alloc, m);
        b.code = r.is_while ? em.while_code(uid) : em.code(r.trip, uid, trip.min, &b.shape);
        b.stages = em.stages();
        return b;
    };
    // Whether the code assembles, in the file (a while loop's entry, or a counted loop's without
    // its zero-trip test, may get nops first).
    auto assembles = [&](Built& b) {
        std::string& code = b.code;
        assembler::AsmResult check = assembler::assemble_string(before + code + after, filename, m, asm_options(opts));
        // A while loop starts with its first pass (the counted loop with its trip test, unless
        // .trip drops it): results of the code before it may still be in flight. As many nops as
        // the assembler's check asks.
        std::uint32_t longest = 1;
        for (std::uint32_t l : m.latency) longest = std::max(longest, l);
        auto clean = [](const assembler::AsmResult& a) { return a.ok && a.warnings == 0; };
        if ((r.is_while || !b.shape.guard) && !clean(check) && longest > 1) {
            // The most nops first: when even they do not help, the fault is not at the entry
            // (one assembly, not one per count); else the fewest that do.
            std::string nops;
            for (std::uint32_t k = 1; k < longest; ++k) nops += "        nop\n";
            assembler::AsmResult most = assembler::assemble_string(before + nops + code + after, filename, m, asm_options(opts));
            if (!clean(most)) check = std::move(most);
            for (std::uint32_t lead = 1; clean(most) && !clean(check) && lead < longest; ++lead) {
                code = "        nop\n" + code;
                ++b.shape.lead;
                check = lead + 1 == longest ? std::move(most)
                                            : assembler::assemble_string(before + code + after, filename, m, asm_options(opts));
            }
        }
        if (!check.ok || check.warnings > 0) {
            why_not = fmt::format("II {}: {}", b.s.ii, check.diagnostics.substr(0, check.diagnostics.find('\n')));
            return false;
        }
        return true;
    };
    auto keep = [&](Built&& b) {
        sched = std::move(b.s);
        emitted = std::move(b.code);
        stages = b.stages;
        alloc_found = std::move(b.alloc);
    };
    // A schedule is kept when its code also assembles.
    auto accept = [&](const Schedule& s) {
        std::optional<Built> b = build(s);
        if (!b || !assembles(*b)) return false;
        keep(std::move(*b));
        return true;
    };
    // Each schedule found is first tried with its ops moved by whole stages to fewer stages and
    // shorter lifetimes (same reservation table), then as found if that one fails to assemble.
    const std::vector<DepEdge> edges = dep_edges(g);
    const std::vector<StageValue> values = stage_values(g);
    int scheduled_count = 0; // modulo schedules found, whether or not their code assembled
    auto shifted = [&](const Schedule& s) {
        ++scheduled_count;
        std::vector<Schedule> out;
        Schedule c = s;
        c.time = shift_stages(edges, values, s.time, s.ii);
        c.normalise();
        if (c.time != s.time) out.push_back(std::move(c));
        out.push_back(s);
        return out;
    };
    // The caller has checked that the dependences admit stage numbers at this II (feasible_ii).
    auto try_ii = [&](int ii, std::optional<Clock::time_point> deadline) {
        if (r.is_while && !deadline) { // of every attempt's schedule, the fewest stages, then the smallest
            // unroll, is the cheapest to enter and to leave (a while loop does both often); the
            // earlier attempt on a tie. Ranked first, then assembled in that order until one does
            // (assembling the file is the expensive step).
            struct Ranked {
                int stages, unroll;
                Schedule s;
            };
            std::vector<Ranked> ranked;
            // Attempts at a stage limit (0: none); under a limit, until one keeps to it.
            auto attempts = [&](int limit) {
                bool within = false;
                for (int attempt = 0; attempt < 2 * kAttemptsPerII && !(within && limit > 0); ++attempt) {
                    std::optional<Schedule> found = ModuloScheduler(g, m, ii, branch, counter, attempt, r.exit_op, limit).run();
                    if (!found) continue;
                    for (Schedule& s : shifted(*found)) {
                        int st = 1;
                        for (int t : s.time) st = std::max(st, t / s.ii + 1);
                        try {
                            ranked.push_back({st, allocate(r, g, s, named, m, filename).unroll, std::move(s)});
                            within = within || limit == 0 || st <= limit;
                        } catch (const RegisterPressure& e) {
                            const std::string what = e.what();
                            why_not = fmt::format("II {}: {}", ii, what.substr(std::min(what.size(), what.find("error: ") + 7)));
                        }
                    }
                }
                std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
                    return std::tie(a.stages, a.unroll) < std::tie(b.stages, b.unroll);
                });
                return within;
            };
            attempts(0);
            // Then each stage fewer than the best so far, as long as some attempt keeps to it: a
            // run pays about (stages - 1) x II to fill and drain, and the loops of a kernel run often.
            int limit = ranked.empty() ? 0 : ranked.front().stages - 1;
            while (limit >= 1 && attempts(limit)) --limit;
            for (const Ranked& k : ranked)
                if (accept(k.s)) return true;
            return false;
        }
        for (int attempt = 0; deadline ? Clock::now() < *deadline : attempt < kAttemptsPerII; ++attempt) {
            std::optional<Schedule> s = ModuloScheduler(g, m, ii, branch, counter, attempt, r.is_while ? r.exit_op : -1).run();
            if (!s) continue;
            for (const Schedule& k : shifted(*s))
                if (accept(k)) return true;
        }
        return false;
    };
    // `.trip`: every schedule found at an II is costed by its whole run at the expected trip
    // count (whole_run_cycles, from the code's shape); they are assembled cheapest first, and the
    // first that assembles is kept when it beats the best so far. At the first II that works, the
    // schedule the rule without .trip takes (the first found that assembles) is assembled first:
    // the report compares with it.
    std::optional<TripChoice> choice;
    const bool by_trip = trip.min > 0 && !r.is_while;
    auto option = [&](const Built& b) {
        TripChoice::Option o;
        static_cast<RunParts&>(o) = whole_run_parts(b.shape, trip.expected);
        o.ii = b.s.ii, o.stages = b.stages, o.unroll = b.alloc.unroll, o.cycles = o.total();
        return o;
    };
    auto try_ii_trip = [&](int ii) {
        std::vector<Built> found;
        std::set<std::vector<int>> seen;
        for (int attempt = 0; attempt < kAttemptsPerII; ++attempt) {
            std::optional<Schedule> s = ModuloScheduler(g, m, ii, branch, counter, attempt, -1).run();
            if (!s) continue;
            for (const Schedule& k : shifted(*s)) {
                if (!seen.insert(k.time).second) continue;
                std::optional<Built> b = build(k);
                if (!b) continue;
                const int copies = b->alloc.unroll;
                found.push_back(std::move(*b));
                // With a taken-branch bubble, the same schedule with 2x and 4x the kernel copies (one
                // bubble per pass, a longer remainder): the whole-run cost decides, within registers.
                if (m.branch_penalty > 0)
                    for (int more = 2 * copies; more <= std::min(4 * copies, kMaxPortUnroll); more *= 2)
                        if (std::optional<Built> c = build(k, more); c && c->alloc.unroll > copies)
                            found.push_back(std::move(*c));
            }
        }
        std::vector<TripChoice::Option> cost;
        for (const Built& b : found) cost.push_back(option(b));
        std::optional<std::size_t> first_ok;
        if (!choice) {
            for (std::size_t k = 0; k < found.size() && !first_ok; ++k)
                if (assembles(found[k])) first_ok = k;
            if (!first_ok) return false;
            cost[*first_ok] = option(found[*first_ok]); // with the nops its entry may have got
            choice = TripChoice{trip.min, trip.expected, trip.line, cost[*first_ok], cost[*first_ok], 0, ii, ii};
        }
        choice->candidates += static_cast<int>(found.size());
        choice->ii_last = ii;
        std::vector<std::size_t> order(found.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { // the smaller code on a tie
            return std::tie(cost[a].cycles, cost[a].stages, cost[a].unroll) < std::tie(cost[b].cycles, cost[b].stages, cost[b].unroll);
        });
        for (std::size_t k : order) {
            if (!first_ok && cost[k].cycles >= choice->chosen.cycles) break;
            // Entry nops (assembles) are known only once assembled: the order is by the cost
            // without them (they are rare: code just before the region feeding it), and one that
            // they make no cheaper than the one to beat is passed over.
            if (k != first_ok) {
                if ((first_ok && k < *first_ok) || !assembles(found[k])) continue; // those before it failed
                const std::int64_t with_nops = option(found[k]).cycles;
                if (first_ok ? with_nops > cost[*first_ok].cycles : with_nops >= choice->chosen.cycles) continue;
            }
            choice->chosen = option(found[k]);
            choice->short_path = found[k].shape.short_path;
            choice->remainder = found[k].shape.remainder();
            keep(std::move(found[k]));
            return true;
        }
        return false;
    };
    int last_tried = hi;
    // Why each II below the one taken failed, for the report: runs of IIs that failed alike.
    struct Tried {
        int first, last;
        int kind; // 0: no stage numbers satisfy the recurrences, 1: no modulo schedule, 2: none assembled
        std::string detail;
    };
    std::vector<Tried> tried;
    for (int ii = lo, unscheduled = 0; ii <= hi; ++ii) {
        const int before_ii = scheduled_count;
        const bool feasible = feasible_ii(g, ii);
        if (feasible && (by_trip ? try_ii_trip(ii) : try_ii(ii, std::nullopt))) break;
        const int kind = !feasible ? 0 : scheduled_count == before_ii ? 1 : 2;
        const std::string detail = kind == 2 ? why_not.substr(std::min(why_not.size(), why_not.find(": ") + 2)) : "";
        if (!tried.empty() && tried.back().kind == kind && tried.back().last + 1 == ii)
            tried.back().last = ii, tried.back().detail = detail;
        else
            tried.push_back({ii, ii, kind, detail});
        unscheduled = scheduled_count == before_ii ? unscheduled + 1 : 0;
        if (opts.max_unscheduled_iis > 0 && unscheduled >= opts.max_unscheduled_iis) {
            last_tried = ii;
            break;
        }
    }
    if (choice) {
        // Larger IIs while one could still be cheaper: the prologue and the kernel passes alone
        // take EXPECTED x II cycles, a remainder iteration at least the sequential copy's length.
        // No further than that length: a kernel pass as long gains nothing on the sequential loop.
        int sequential = 1 + std::max(1, static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]));
        for (const Node& nd : g.nodes) sequential += std::max(1, nd.latency);
        for (int ii = sched->ii + 1; ii <= std::min(hi, sequential); ++ii) {
            if (static_cast<std::int64_t>(trip.expected) * std::min(ii, sequential) >= choice->chosen.cycles) break;
            choice->ii_last = ii;
            if (feasible_ii(g, ii)) try_ii_trip(ii);
        }
    }
    // --exact: branch and bound at each II from the bound up to the one found; the first II with
    // a schedule that assembles is the answer, and it is proven optimal when every II below it
    // was exhausted with no modulo schedule at all.
    std::string exact_note;
    if (sched && opts.exact_seconds > 0) {
        if (choice) {
            exact_note = "--exact is not combined with .trip yet (the schedule is chosen by whole-run cycles)";
        } else if (r.is_while && sched->ii > res.mii) {
            exact_note = "--exact is not implemented for .pipeline while loops yet (heuristic schedule only)";
        } else if (sched->ii == res.mii) {
            exact_note = "II proven optimal: it equals the lower bound max(ResMII, RecMII)";
        } else {
            const auto start = Clock::now();
            const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opts.exact_seconds));
            const int found = sched->ii;
            std::uint64_t nodes = 0;
            int proven_below = res.mii; // every II in [res.mii, proven_below) has no modulo schedule
            std::string open;           // why the bound is not proven
            for (int ii = res.mii; ii < found; ++ii) {
                if (!feasible_ii(g, ii)) {
                    if (open.empty()) proven_below = ii + 1;
                    continue;
                }
                // With a branch bubble: first a search with the bubble's rules (its tables mostly
                // assemble), then the proof, without them (they are exact only for a kernel that
                // is not unrolled).
                ExactScheduler::Outcome o = ExactScheduler::Outcome::Exhausted;
                std::uint64_t tables = 0;
                for (const bool bubble : {true, false}) {
                    if (bubble && m.branch_penalty == 0) continue;
                    ExactScheduler ex(g, m, ii, branch, counter, deadline, bubble);
                    o = ex.run(accept);
                    nodes += ex.nodes();
                    tables = ex.tables();
                    if (o != ExactScheduler::Outcome::Exhausted) break;
                }
                if (o == ExactScheduler::Outcome::Accepted) break;
                if (o == ExactScheduler::Outcome::Timeout) {
                    open = fmt::format("II {} undecided after {} s{}", ii, opts.exact_seconds,
                                       tables ? fmt::format(" ({} modulo schedule{} found did not assemble; the last: {})",
                                                            tables, tables == 1 ? "" : "s",
                                                            why_not.substr(std::min(why_not.size(), why_not.find("error: ") + 7)))
                                              : "");
                    break;
                }
                if (tables > 0 && open.empty())
                    open = fmt::format("II {} has {} modulo schedule{} but none assembles", ii, tables, tables == 1 ? "" : "s");
                if (open.empty()) proven_below = ii + 1;
            }
            const double secs = std::chrono::duration<double>(Clock::now() - start).count();
            const std::string searched = fmt::format("branch and bound, {} nodes in {:.2f} s", nodes, secs);
            const std::string improved = sched->ii < found ? fmt::format(" (the heuristic found II {})", found) : "";
            if (open.empty() && proven_below >= sched->ii)
                exact_note = sched->ii > res.mii
                                 ? fmt::format("II proven optimal{}: no modulo schedule at II {}..{} ({})", improved, res.mii,
                                               sched->ii - 1, searched)
                                 : fmt::format("II proven optimal{}: it equals the lower bound ({})", improved, searched);
            else
                exact_note = fmt::format("best found{}, bound not proven: {}{} ({})", improved, open,
                                         proven_below > res.mii ? fmt::format("; none at II {}..{}", res.mii, proven_below - 1) : "",
                                         searched);
        }
    }
    if (!sched)
        fail(filename, static_cast<int>(r.begin + 1),
             fmt::format("no modulo schedule found for II {}..{} (MII {}){}", lo, last_tried, res.mii,
                         why_not.empty() ? "" : "; the last that scheduled did not assemble: " + why_not));
    const Allocation& alloc = *alloc_found;
    res.ii = sched->ii;
    res.stages = stages;
    res.unroll = alloc.unroll;
    res.min_pipelined_trip = r.is_while ? 0 : res.stages - 1 + res.unroll;
    res.trip_register = r.trip;
    if (r.is_while) res.exit_stage = sched->time[static_cast<std::size_t>(r.exit_op)] / sched->ii;
    res.scratch = alloc.scratch;
    res.min_trip = by_trip ? trip.min : 0;
    res.loops = {{static_cast<int>(r.begin + 1), r.is_while, res.ii, res.mii, res.res_mii, res.rec_mii, res.stages, res.unroll, choice, {}}};
    for (const auto& [f, reg] : named) res.source_registers.push_back(reg_name(static_cast<isa::RegFile>(f), reg));

    std::string rep;
    rep += fmt::format("# SOFTWARE PIPELINE INFORMATION ({} on {}, lines {}-{})\n", filename, m.name, r.begin + 1, r.end + 1);
    if (r.is_while)
        rep += fmt::format("#   operations per iteration   {} (a while loop: its exit test is the kernel's branch)\n", r.ops.size());
    else
        rep += fmt::format("#   operations per iteration   {} (+ 2 for loop control in the kernel)\n", r.ops.size());
    rep += fmt::format("#   resource bound (ResMII)    {}  ({}, loop control included)\n", res.res_mii, res_bound.binds);
    const std::vector<int> critical = critical_edges(g, res.rec_mii);
    const std::string circuit = critical_circuit(g, r, critical);
    rep += fmt::format("#   recurrence bound (RecMII)  {}{}\n", res.rec_mii, circuit.empty() ? "" : "  (" + circuit + ")");
    if (const std::string hint = alias_hint(g, critical); !hint.empty()) rep += "#     " + hint + "\n";
    rep += fmt::format("#   ii = {}  schedule found with {} iteration{} in parallel{}\n", res.ii, res.stages,
                       res.stages == 1 ? "" : "s", res.ii == res.mii ? " (at the bound)" : fmt::format(" ({} above the MII)", res.ii - res.mii));
    if (!tried.empty()) {
        std::string why;
        for (const Tried& t : tried) {
            const std::string iis = t.first == t.last ? fmt::format("II {}", t.first) : fmt::format("IIs {}..{}", t.first, t.last);
            why += fmt::format("{}{}: {}", why.empty() ? "" : "; ", iis,
                               t.kind == 0   ? "no stage numbers satisfy the recurrences"
                               : t.kind == 1 ? "no modulo schedule found"
                                             : "schedules found, none assembled (the last: " + t.detail + ")");
        }
        rep += fmt::format("#   below it: {}\n", why);
    }
    if (!exact_note.empty()) rep += "#   " + exact_note + "\n";
    rep += fmt::format("#   kernel unrolled {}x (modulo variable expansion)\n", res.unroll);
    if (m.branch_penalty > 0)
        rep += fmt::format("#   taken-branch bubble {} cycle{} per kernel pass: {:.2f} cycles per iteration in the kernel\n",
                           m.branch_penalty, m.branch_penalty == 1 ? "" : "s",
                           static_cast<double>(res.unroll * res.ii + static_cast<int>(m.branch_penalty)) / res.unroll);
    if (alloc.entry_nops > 0)
        rep += fmt::format("#   kernel entered after {} nop{} (as long as the bubble, so writes from the prologue and from the "
                           "back edge meet no others on a port)\n", alloc.entry_nops, alloc.entry_nops == 1 ? "" : "s");
    if (r.is_while)
        rep += while_report(g, r, *sched, res);
    else if (choice && !choice->short_path)
        rep += fmt::format("#   minimum pipelined trip count {} (.trip's minimum is at least that: no sequential copy for short "
                           "trips{})\n", res.min_pipelined_trip, choice->remainder ? "; the unroll remainder runs it" : " and no remainder");
    else
        rep += fmt::format("#   minimum pipelined trip count {} (fewer, and the unroll remainder, run the sequential copy)\n",
                           res.min_pipelined_trip);
    if (choice) rep += choice->text();
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        std::string regs;
        for (const std::string& s : alloc.regs[v]) regs += (regs.empty() ? "" : " ") + s;
        rep += fmt::format("#   {:<10} lifetime {:>3} cycles -> {}\n", r.virtuals[v].name, alloc.lifetime[v], regs);
    }
    std::vector<TableRow> rows = schedule_rows(g, r, *sched, m);
    rep += mrt_text(rows);
    res.report = rep;
    {
        LoopReport picture = schedule_picture(g, r, *sched, std::move(rows), alloc.lifetime, m, filename,
                                              res.ii == res.mii ? "at the bound" : fmt::format("{} above the MII", res.ii - res.mii));
        picture.res_mii = res.res_mii;
        picture.rec_mii = res.rec_mii;
        res.loops[0].svg = picture.svg();
    }

    res.code = code_before + emitted + after;
    res.pipelined = header + rep + res.code;
    res.pipelined_region_at = header.size() + rep.size() + code_before.size();
    impl.emitted = emitted;
    return impl;
}

} // namespace

PipelineResult pipeline_source(std::string_view text, std::string_view filename, const isa::Machine& m,
                               const PipelineOptions& opts) {
    std::vector<std::string> lines = split_lines(machine_sections(text, filename, m));
    const std::size_t n = region_spans(lines, filename).size();
    if (opts.region || n == 1) {
        Target t;
        t.index = opts.region.value_or(0);
        t.ordinal = static_cast<int>(t.index);
        PipelineResult r = pipeline_impl(text, filename, m, opts, Upto::Pipelined, t).res;
        r.regions = static_cast<int>(n);
        return r;
    }
    // Several regions: one after another, the last first (so each one's lines, and those before
    // it, keep their numbers in reports and errors), each scheduled with the later ones as their
    // pipelined code and the earlier ones as their sequential meanings; a region's scratch
    // registers are free again for the next (they are live only inside it).
    const std::string linear = pipeline_impl(text, filename, m, opts, Upto::Linear).res.linear; // every region sequential
    PipelineResult all;
    std::string reports;
    std::vector<LoopSummary> loops;
    Target t;
    for (std::size_t k = n; k-- > 0;) {
        t.index = k;
        t.ordinal = static_cast<int>(k);
        std::string current;
        for (const std::string& l : lines) current += l + "\n";
        Impl step = pipeline_impl(current, filename, m, opts, Upto::Pipelined, t);
        all = step.res;
        reports = step.res.report + reports;
        loops.insert(loops.begin(), step.res.loops.begin(), step.res.loops.end());
        for (const std::string& reg : step.res.scratch) {
            isa::RegFile f;
            int num = 0;
            if (parse_reg(reg, f, num)) t.reusable.insert({static_cast<int>(f), num});
        }
        std::vector<std::string> spliced(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(step.span.first));
        for (const std::string& l : split_lines(step.emitted)) spliced.push_back(l);
        spliced.insert(spliced.end(), lines.begin() + static_cast<std::ptrdiff_t>(step.span.second + 1), lines.end());
        lines = std::move(spliced);
    }
    std::string code;
    for (const std::string& l : lines) code += l + "\n";
    if (!assembler::header_machine(code).empty()) code = code.substr(code.find('\n') + 1);
    all.regions = static_cast<int>(n);
    all.linear_region_at.reset(); // the offsets of one region's files, not of these
    all.pipelined_region_at.reset();
    all.linear = linear;
    all.loops = loops;
    all.report = reports;
    all.code = code;
    all.pipelined = fmt::format("# machine: {}\n", m.reference()) + reports + code;
    return all;
}

std::string sequential_region(std::string_view text, std::string_view filename, const isa::Machine& m) {
    return pipeline_impl(text, filename, m, {}, Upto::Markers).res.linear;
}

std::vector<int> region_lines(std::string_view text, std::string_view filename, const isa::Machine& m) {
    std::vector<int> out;
    for (const Span& s : region_spans(split_lines(machine_sections(text, filename, m)), filename)) out.push_back(static_cast<int>(s.first + 1));
    return out;
}

std::string restore_region(std::string_view legalized, std::string_view original) {
    // The original's regions, .pipeline to .endpipeline, in order: the k-th goes back between the
    // k-th pair of markers.
    std::vector<std::string> regions;
    bool in_region = false;
    for (const std::string& o : split_lines(original)) {
        const std::string code = strip_comment(o);
        if (opens_region(code)) {
            in_region = true;
            regions.emplace_back();
        }
        if (in_region) regions.back() += o + "\n";
        if (code == ".endpipeline") in_region = false;
    }
    std::string out;
    bool inside = false;
    std::size_t next = 0;
    for (const std::string& l : split_lines(legalized)) {
        if (l == kRegionBegin) {
            inside = true;
            if (next < regions.size()) out += regions[next++];
            continue;
        }
        if (l == kRegionEnd) {
            inside = false;
            continue;
        }
        if (!inside) out += l + "\n";
    }
    return out;
}

} // namespace nesshi::sched
