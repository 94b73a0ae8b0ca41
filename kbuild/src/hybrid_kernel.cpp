#include "hybrid_kernel.hpp"

#include "assembler/op_text.hpp"
#include "base/lines.hpp"
#include "isa/ops.hpp"
#include "kernels/abi.hpp"

#include <fmt/format.h>

#include <map>
#include <regex>
#include <set>
#include <string_view>
#include <vector>

namespace nesshi::kbuild::detail {

namespace {

using Lines = std::vector<std::string>;

// The label a line defines ("name:" alone, maybe before a comment), or "".
std::string label_of(const std::string& line) {
    static const std::regex label(R"(^([A-Za-z_.][A-Za-z0-9_.]*):\s*(#.*)?$)");
    std::smatch m;
    return std::regex_match(line, m, label) ? m[1].str() : std::string();
}

std::optional<std::size_t> label_line(const Lines& lines, std::string_view name) {
    for (std::size_t i = 0; i < lines.size(); ++i)
        if (label_of(lines[i]) == name) return i;
    return std::nullopt;
}

// The operations of lines [from, to): "li r0, 0", one per op of a bundle, without comments.
std::vector<std::string> ops_of(const Lines& lines, std::size_t from, std::size_t to) {
    std::vector<std::string> out;
    for (std::size_t i = from; i < to; ++i) {
        std::string code = lines[i].substr(0, lines[i].find('#'));
        if (!label_of(lines[i]).empty() || code.find_first_not_of(" \t") == std::string::npos) continue;
        for (char& c : code)
            if (c == '{' || c == '}') c = ';';
        std::size_t at = 0;
        while (at <= code.size()) {
            const std::size_t end = std::min(code.find(';', at), code.size());
            std::string op = code.substr(at, end - at);
            const std::size_t a = op.find_first_not_of(" \t"), b = op.find_last_not_of(" \t");
            if (a != std::string::npos && op[a] != '.') out.push_back(op.substr(a, b - a + 1));
            at = end + 1;
        }
    }
    return out;
}

// The register an operation writes ("r0" of "li r0, 0", "r2" of "iu0: recv r2, CH_IN"), or ""
// (stores, branches, sends, nop): its first operand where the operation table says it is one.
std::string written(const std::string& op) {
    const assembler::OperationText t = assembler::split_operation(op);
    const auto opcode = isa::find_opcode(t.mnemonic);
    if (!opcode || t.operands.empty()) return "";
    const isa::OpInfo& info = isa::kOps[*opcode];
    return info.num_operands > 0 && info.operands[0].is_dest ? t.operands[0].text : "";
}

std::set<std::string> mentioned(const std::vector<std::string>& ops) {
    static const std::regex reg(R"(\b[rf][0-9]+\b)");
    std::set<std::string> out;
    for (const std::string& op : ops)
        for (auto it = std::sregex_iterator(op.begin(), op.end(), reg); it != std::sregex_iterator(); ++it) out.insert(it->str());
    return out;
}

// Register -> the operations of `ops` that write it.
std::map<std::string, std::set<std::string>> writers(const std::vector<std::string>& ops) {
    std::map<std::string, std::set<std::string>> out;
    for (const std::string& op : ops)
        if (const std::string r = written(op); !r.empty()) out[r].insert(op);
    return out;
}

// Lines [from, to) with IC_JUMPS_A renamed IC_JUMPS_L (when `table`) and each of `labels` suffixed _loops.
std::string renamed(const Lines& lines, std::size_t from, std::size_t to, bool table, const std::set<std::string>& labels) {
    static const std::regex jumps(R"(\bIC_JUMPS_A\b)"), word(R"([A-Za-z_.][A-Za-z0-9_.]*)");
    std::string out;
    for (std::size_t i = from; i < to; ++i) {
        std::string line = table ? std::regex_replace(lines[i], jumps, "IC_JUMPS_L") : lines[i];
        std::string r;
        auto last = line.cbegin();
        for (auto it = std::sregex_iterator(line.begin(), line.end(), word); it != std::sregex_iterator(); ++it) {
            r.append(last, (*it)[0].first);
            r += it->str() + (labels.count(it->str()) ? "_loops" : "");
            last = (*it)[0].second;
        }
        r.append(last, line.cend());
        out += r + "\n";
    }
    return out;
}

std::string joined(const Lines& lines, std::size_t from, std::size_t to) {
    std::string out;
    for (std::size_t i = from; i < to; ++i) out += lines[i] + "\n";
    return out;
}

std::string long_label(std::uint32_t long_from) {
    return std::string(kernels::abi::kListsLongPrefix) + std::to_string(long_from) + ":";
}

} // namespace

HybridText hybrid_kernel_text(const std::string& dispatch, const std::string& loops, std::uint32_t long_from) {
    const Lines d = base::split_lines(dispatch), l = base::split_lines(loops);
    const auto l_hybrid = label_line(l, "hybrid_start");
    if (!l_hybrid) return {};
    const auto d_start = label_line(d, "start"), d_next = label_line(d, "next_ray");
    const auto l_start = label_line(l, "start"), l_next = label_line(l, "next_ray"), l_entry = label_line(l, "from_dispatch");
    if (!d_start || !d_next || !l_start || !l_next || !l_entry || *d_next < *d_start || *l_next < *l_start || *l_entry < *l_hybrid)
        return {std::nullopt, "a kernel lacks start, next_ray or from_dispatch, or has them out of order"};
    // What each part sets up once must survive the other: the loops' start runs after the
    // dispatch kernel's, so a register it writes that the dispatch kernel uses later must be
    // written by the same operation in the dispatch kernel's start (the same value); a register
    // either start writes that its own part uses later must not be written by the other part.
    const std::vector<std::string> d_setup = ops_of(d, *d_start, *d_next), d_rest = ops_of(d, *d_next, d.size());
    std::vector<std::string> l_setup = ops_of(l, *l_start, *l_next);
    const std::vector<std::string> l_once = ops_of(l, *l_hybrid, *l_entry), l_rest = ops_of(l, *l_entry, l.size());
    l_setup.insert(l_setup.end(), l_once.begin(), l_once.end());
    const auto d_setup_writes = writers(d_setup), d_rest_writes = writers(d_rest), l_setup_writes = writers(l_setup),
               l_rest_writes = writers(l_rest);
    const std::set<std::string> d_uses = mentioned(d_rest), l_uses = mentioned(l_rest);
    for (const auto& [reg, ops] : l_setup_writes) {
        if (d_rest_writes.count(reg) && l_uses.count(reg))
            return {std::nullopt, fmt::format("the dispatch kernel writes {}, which the loops set up once", reg)};
        const auto same = d_setup_writes.find(reg);
        if (d_uses.count(reg) && (same == d_setup_writes.end() || same->second != ops))
            return {std::nullopt, fmt::format("the loops' start sets {} to another value than the dispatch kernel's", reg)};
    }
    for (const auto& [reg, ops] : d_setup_writes)
        if (d_uses.count(reg) && l_rest_writes.count(reg))
            return {std::nullopt, fmt::format("the loops write {}, which the dispatch kernel sets up once", reg)};
    // The loops' labels that the dispatch kernel defines too get a suffix.
    std::set<std::string> d_labels, clash;
    for (const std::string& line : d)
        if (const std::string name = label_of(line); !name.empty()) d_labels.insert(name);
    for (std::size_t i = *l_entry; i < l.size(); ++i)
        if (const std::string name = label_of(l[i]); d_labels.count(name)) clash.insert(name);
    std::string out = joined(d, 0, *d_start);
    out += long_label(long_from) + "\n";
    out += joined(d, *d_start, *d_next);
    out += "# ---- the loops' start (intersect.loops.pk), their table renamed IC_JUMPS_L ----\n";
    out += renamed(l, *l_start + 1, *l_next, true, clash);
    out += joined(l, *l_hybrid, *l_entry);
    out += joined(d, *d_next, d.size());
    out += "# ---- the loops (intersect.loops.pk): entered from a LOOPS record ----\n";
    out += renamed(l, *l_entry, l.size(), true, clash);
    return {out, ""};
}

std::string with_long_from(const std::string& text, std::uint32_t long_from) {
    static const std::regex label("^" + std::string(kernels::abi::kListsLongPrefix) + "[0-9]+:$", std::regex::multiline);
    return std::regex_replace(text, label, long_label(long_from), std::regex_constants::format_first_only);
}

} // namespace nesshi::kbuild::detail
