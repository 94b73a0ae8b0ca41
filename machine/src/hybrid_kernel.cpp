#include "hybrid_kernel.hpp"

#include "kernels/abi.hpp"

#include <regex>
#include <string_view>
#include <vector>

namespace nesshi::machine::detail {

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t eol = text.find('\n', at);
        out.push_back(text.substr(at, eol == std::string::npos ? std::string::npos : eol - at));
        if (eol == std::string::npos) break;
        at = eol + 1;
    }
    return out;
}

// The index of the line that defines `label` ("label:" alone on its line), or none.
std::optional<std::size_t> label_line(const std::vector<std::string>& lines, std::string_view label) {
    const std::string want = std::string(label) + ":";
    for (std::size_t i = 0; i < lines.size(); ++i)
        if (lines[i] == want) return i;
    return std::nullopt;
}

// Lines [from, to) of `lines` with the loops' names that would meet the dispatch kernel's renamed.
std::string renamed(const std::vector<std::string>& lines, std::size_t from, std::size_t to) {
    static const std::regex table(R"(\bIC_JUMPS_A\b)"), end(R"(\b(done|return|hit)\b)");
    std::string out;
    for (std::size_t i = from; i < to; ++i)
        out += std::regex_replace(std::regex_replace(lines[i], table, "IC_JUMPS_L"), end, "$1_loops") + "\n";
    return out;
}

std::string joined(const std::vector<std::string>& lines, std::size_t from, std::size_t to) {
    std::string out;
    for (std::size_t i = from; i < to; ++i) out += lines[i] + "\n";
    return out;
}

} // namespace

std::optional<std::string> hybrid_kernel_text(const std::string& dispatch, const std::string& loops, std::uint32_t long_from) {
    const std::vector<std::string> d = lines_of(dispatch), l = lines_of(loops);
    const auto d_start = label_line(d, "start"), d_next = label_line(d, "next_ray");
    const auto l_start = label_line(l, "start"), l_next = label_line(l, "next_ray"), l_hybrid = label_line(l, "hybrid_start"),
               l_entry = label_line(l, "from_dispatch");
    if (!d_start || !d_next || !l_start || !l_next || !l_hybrid || !l_entry || *d_next < *d_start || *l_next < *l_start ||
        *l_entry < *l_hybrid)
        return std::nullopt;
    std::string out = joined(d, 0, *d_start);
    out += std::string(kernels::abi::kListsLongPrefix) + std::to_string(long_from) + ":\n";
    out += joined(d, *d_start, *d_next);
    out += "# ---- the loops' start (intersect.loops.pk), their table renamed IC_JUMPS_L ----\n";
    out += renamed(l, *l_start + 1, *l_next);
    out += joined(l, *l_hybrid, *l_entry);
    out += joined(d, *d_next, d.size());
    out += "# ---- the loops (intersect.loops.pk): entered from a LOOPS record ----\n";
    out += renamed(l, *l_entry, l.size());
    return out;
}

} // namespace nesshi::machine::detail
