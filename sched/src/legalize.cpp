// Nop insertion until hand-scheduled code is legal on a machine (sched/legalize.hpp).
#include "sched/legalize.hpp"

#include "text.hpp"

#include "base/error.hpp"

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
                             R"(:(\d+):\d+: error: (.*)$)");
    for (int round = 0; round < 256; ++round) {
        const std::optional<std::string> diags = check(out.text);
        if (!diags) {
            for (const auto& [line, n] : added) out.where.push_back(fmt::format("{}: {} nop{}", line, n, n == 1 ? "" : "s"));
            return out;
        }
        std::map<std::size_t, int> need; // 0-based line of the current text -> nops
        bool other = false;
        for (const std::string& d : split_lines(*diags)) {
            std::smatch m;
            if (d.find(": error: ") == std::string::npos || d.rfind(filename + ": error: ", 0) == 0) continue; // a summary
            if (!std::regex_match(d, m, located)) { other = true; break; }
            const int n = nops_for(m[2]);
            const std::size_t line = static_cast<std::size_t>(std::stoul(m[1])) - 1;
            if (n == 0 || line >= lines.size()) { other = true; break; }
            int& slot = need[insertion_line(lines, line)];
            slot = std::max(slot, n);
        }
        if (other || need.empty()) throw base::Error(*diags);
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
