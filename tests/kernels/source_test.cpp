// kernels/ic/intersect.pk writes each primitive body once, variant A (payload buffer f30-f46,
// record base r10, prefetching into B through IC_JUMPS_B), and `#copy` makes variant B (the
// reverse): the modulo variable expansion of the payload buffer. Checked here with a swap written
// independently of sched::expand_copies, so a copy that swapped too much or too little fails.
#include "support.hpp"

#include "kernels/sources.hpp"
#include "sched/block.hpp"

#include <map>
#include <regex>
#include <sstream>

using namespace nesshi;
using namespace nesshi::kernels;

namespace {

// label -> the body's lines up to its `#pack end`
std::map<std::string, std::vector<std::string>> bodies(const std::string& text) {
    std::map<std::string, std::vector<std::string>> out;
    std::istringstream in(text);
    std::string line, label;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == ':' && line.find(' ') == std::string::npos) {
            label = line.substr(0, line.size() - 1);
            continue;
        }
        if (label.empty()) continue;
        out[label].push_back(line);
        if (line == "#pack end") label.clear();
    }
    return out;
}

// A's registers and table as B's, and B's as A's, in one pass; comments as written.
std::string swap_variant(const std::string& whole) {
    const std::size_t hash = whole.find('#');
    if (hash != std::string::npos) return swap_variant(whole.substr(0, hash)) + whole.substr(hash);
    const std::string& line = whole;
    static const std::regex token(R"(\bf(\d+)\b|\br1[01]\b|IC_JUMPS_[AB]\b|_[AB]\b)");
    std::string out;
    auto begin = std::sregex_iterator(line.begin(), line.end(), token);
    std::size_t pos = 0;
    for (auto it = begin; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        out.append(line, pos, static_cast<std::size_t>(m.position()) - pos);
        const std::string t = m.str();
        if (t[0] == 'f') {
            const int r = std::stoi(m[1].str());
            out += "f" + std::to_string(r >= 30 && r <= 46 ? r + 20 : r >= 50 && r <= 66 ? r - 20 : r);
        } else if (t == "r10") out += "r11";
        else if (t == "r11") out += "r10";
        else out += t.substr(0, t.size() - 1) + (t.back() == 'A' ? "B" : "A");
        pos = static_cast<std::size_t>(m.position() + m.length());
    }
    out.append(line, pos, std::string::npos);
    return out;
}

} // namespace

TEST_CASE("the IC kernel's B bodies are its A bodies with the payload buffers swapped", "[unit][kernels]") {
    const std::string pk = embedded().text("ic/intersect.pk");
    CHECK(bodies(pk).count("tri1_B") == 0); // written once
    const auto b = bodies(sched::expand_copies(pk, "ic/intersect.pk"));
    int pairs = 0;
    for (const auto& [label, lines] : b) {
        if (label.size() < 2 || label.substr(label.size() - 2) != "_A") continue;
        const std::string twin = label.substr(0, label.size() - 2) + "_B";
        INFO(label << " and " << twin);
        REQUIRE(b.count(twin) == 1);
        const std::vector<std::string>& other = b.at(twin);
        REQUIRE(lines.size() == other.size());
        for (std::size_t k = 0; k < lines.size(); ++k) CHECK(swap_variant(lines[k]) == other[k]);
        ++pairs;
    }
    CHECK(pairs == 7); // tri1, tri2, quad1, quad2, sph1, sph2, ball1
}
