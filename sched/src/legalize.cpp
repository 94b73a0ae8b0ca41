// Nop insertion until hand-scheduled code is legal on a machine (sched/legalize.hpp).
#include "sched/legalize.hpp"

#include "text.hpp"

#include "assembler/op_text.hpp"
#include "base/error.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <regex>

namespace nesshi::sched {

namespace {

// The nops an error asks for before its line, or 0 when it is not one legalize() fixes.
int nops_for(const std::string& message) {
    static const std::regex in_flight(R"(is read before its new value lands: '.*' was issued (\d+) cycles? earlier.* and has latency (\d+))");
    std::smatch m;
    if (std::regex_search(message, m, in_flight)) return std::max(1, std::stoi(m[2]) - std::stoi(m[1]));
    // A write landing at or before an earlier one: delay it until it lands one cycle after.
    static const std::regex write_order(R"(is written before an earlier write to it lands: this result lands in cycle \+(\d+), the earlier '.*' in cycle \+(\d+))");
    if (std::regex_search(message, m, write_order)) return std::stoi(m[2]) - std::stoi(m[1]) + 1;
    if (message.find("writes land in one cycle") != std::string::npos) return 1;
    if (message.find("is written twice in one cycle") != std::string::npos) return 1;
    return 0;
}

// A bundle written on one line, `{ a ; b ; c }`, that reads more registers than the machine has
// read ports, or whose results need more write ports in one cycle: the op at `col` (1-based, the
// error's caret) goes into a bundle of its own just before, issuing a cycle earlier. That keeps the meaning when nothing else in the bundle
// names its destination (the others still read the old value; its own sources are checked
// again, and a value it now reads in flight gets nops) and it is neither a FIFO word (their order
// is their slot order), a store (a load beside it reads the old memory) nor control. The two lines, or nothing when the op cannot move.
std::optional<std::pair<std::string, std::string>> split_off(const std::string& line, std::size_t col) {
    const std::size_t open = line.find('{'), close = line.rfind('}');
    if (open == std::string::npos || close == std::string::npos || col == 0 || col - 1 <= open || col - 1 >= close) return std::nullopt;
    std::vector<std::string> ops; // the bundle's ops as written (a slot prefix kept)
    std::size_t moved = 0;
    for (std::size_t at = open + 1; at < close;) {
        const std::size_t end = std::min(line.find(';', at), close);
        if (col - 1 >= at && col - 1 < end) moved = ops.size();
        ops.push_back(trim(line.substr(at, end - at)));
        at = end + 1;
    }
    if (ops.size() < 2) return std::nullopt;
    const std::string op = ops[moved];
    const assembler::OperationText split = assembler::split_operation(op);
    const auto opcode = isa::find_opcode(split.mnemonic);
    if (!opcode || split.operands.empty()) return std::nullopt;
    const isa::OpInfo& info = isa::kOps[*opcode];
    switch (info.kind) {
    case isa::Kind::Store: case isa::Kind::Send: case isa::Kind::Recv: case isa::Kind::Branch: case isa::Kind::Jump:
    case isa::Kind::JumpLink: case isa::Kind::JumpReg: case isa::Kind::Halt: return std::nullopt;
    default: break;
    }
    if (info.num_operands == 0 || !info.operands[0].is_dest) return std::nullopt;
    const std::regex named("(^|[^A-Za-z0-9_])" + split.operands[0].text + "([^0-9A-Za-z_]|$)");
    ops.erase(ops.begin() + static_cast<std::ptrdiff_t>(moved));
    std::string rest;
    for (const std::string& o : ops) {
        if (std::regex_search(o, named)) return std::nullopt; // the others must not see the new value
        rest += (rest.empty() ? "" : " ; ") + o;
    }
    const std::string head = line.substr(0, open), tail = line.substr(close + 1);
    // A label before the bundle stays before the moved op: a jump to it runs both.
    return std::pair{head + "{ " + op + " }", std::string(head.size(), ' ') + "{ " + rest + " }" + tail};
}

// The line a nop for `line` goes before: the `#pack begin` of the block holding it, if any.
std::size_t insertion_line(const std::vector<std::string>& lines, std::size_t line) {
    for (std::size_t k = line; k-- > 0;) {
        if (lines[k].find("#pack end") != std::string::npos) break;
        if (lines[k].find("#pack begin") != std::string::npos) return k;
    }
    return line;
}

} // namespace

Legalized legalize(const std::string& text, const std::string& filename,
                   const std::function<std::optional<std::string>(const std::string&)>& check) {
    Legalized out;
    out.text = text;
    std::vector<int> origin; // line of the current text -> line of the original (1-based), 0 = inserted
    std::vector<std::string> lines = split_lines(text);
    for (std::size_t i = 0; i < lines.size(); ++i) origin.push_back(static_cast<int>(i) + 1);
    std::map<int, int> added; // original line -> nops before it
    const std::regex located("^" + std::regex_replace(filename, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                             R"(:(\d+):(\d+): error: (.*)$)");
    for (int round = 0; round < 256; ++round) {
        const std::optional<std::string> diags = check(out.text);
        if (!diags) {
            for (const auto& [line, n] : added) out.where.push_back(fmt::format("{}: {} nop{}", line, n, n == 1 ? "" : "s"));
            return out;
        }
        std::map<std::size_t, int> need; // 0-based line of the current text -> nops
        std::map<std::size_t, std::size_t> split; // 0-based line -> the column of an op to move out
        bool other = false;
        for (const std::string& d : split_lines(*diags)) {
            std::smatch m;
            if (d.find(": error: ") == std::string::npos || d.rfind(filename + ": error: ", 0) == 0) continue; // a summary
            if (!std::regex_match(d, m, located)) { other = true; break; }
            const std::size_t line = static_cast<std::size_t>(std::stoul(m[1])) - 1;
            const std::string& what = m[3];
            const bool ports = (what.rfind("bundle needs more than", 0) == 0 && what.find("write ports in cycle") != std::string::npos) ||
                               (what.rfind("bundle needs ", 0) == 0 && what.find(" read ports; ") != std::string::npos);
            if (ports) {
                if (line >= lines.size() || !split_off(lines[line], std::stoul(m[2]))) { other = true; break; }
                split.emplace(line, std::stoul(m[2])); // the first error of a line
                continue;
            }
            const int n = nops_for(m[3]);
            if (n == 0 || line >= lines.size()) { other = true; break; }
            int& slot = need[insertion_line(lines, line)];
            slot = std::max(slot, n);
        }
        if (other || (need.empty() && split.empty())) throw base::Error(*diags);
        if (!split.empty()) { // one round of splits alone: the nops of this round's diagnostics may be stale
            for (auto it = split.rbegin(); it != split.rend(); ++it) {
                const auto parts = split_off(lines[it->first], it->second);
                lines[it->first] = parts->second;
                lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(it->first), parts->first);
                origin.insert(origin.begin() + static_cast<std::ptrdiff_t>(it->first), 0);
                ++out.splits;
            }
            out.text.clear();
            for (const std::string& l : lines) out.text += l + "\n";
            continue;
        }
        // From the bottom, so earlier line numbers stay valid.
        for (auto it = need.rbegin(); it != need.rend(); ++it) {
            std::size_t at = it->first;
            std::string& target = lines[at];
            std::string indent = target.substr(0, target.find_first_not_of(" \t"));
            // A label on the bundle's line stays before the nops: jumps to it must wait too.
            static const std::regex label_line(R"(^(\s*[A-Za-z_.][A-Za-z0-9_.$]*:)\s*(\S.*)$)");
            std::smatch lm;
            if (std::regex_match(target, lm, label_line) && lm[2].str()[0] != '#') {
                const std::string label = lm[1], rest = lm[2];
                target = indent.empty() ? std::string(8, ' ') + rest : indent + rest;
                lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), label);
                origin.insert(origin.begin() + static_cast<std::ptrdiff_t>(at), origin[at]);
                ++at;
                indent = std::string(8, ' ');
            }
            if (indent.empty()) indent = std::string(8, ' ');
            lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::size_t>(it->second),
                         indent + "nop # inserted: a value is still in flight on this machine");
            origin.insert(origin.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::size_t>(it->second), 0);
            added[origin[at + static_cast<std::size_t>(it->second)]] += it->second;
            out.nops += it->second;
        }
        out.text.clear();
        for (const std::string& l : lines) out.text += l + "\n";
    }
    throw base::Error(fmt::format("{}: no legal schedule after inserting {} nops", filename, out.nops));
}

} // namespace nesshi::sched
