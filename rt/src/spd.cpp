// SPD name handling and dispatch to the generators.
#include "rt/spd.hpp"

#include "spd_gen.hpp"

#include <fmt/format.h>

#include <charconv>
#include <stdexcept>

namespace nesshi::rt {

const std::vector<std::string>& spd_names() {
    static const std::vector<std::string> names = {"balls", "mount", "rings", "tetra", "tree"};  // the paper's five
    return names;
}

int spd_default_size(std::string_view name) {
    if (name == "balls") return 4;
    if (name == "mount") return 6;
    if (name == "rings") return 7;
    if (name == "tetra") return 6;
    if (name == "tree") return 11;
    if (name == "gears") return 4;
    return 0;
}

std::optional<SpdName> parse_spd_name(std::string_view text) {
    std::string_view base = text, size;
    if (auto c = text.find(':'); c != std::string_view::npos) {
        base = text.substr(0, c);
        size = text.substr(c + 1);
    }
    if (spd_default_size(base) == 0) return std::nullopt;
    SpdName n{std::string(base), 0};
    if (!size.empty()) {
        auto [p, ec] = std::from_chars(size.data(), size.data() + size.size(), n.size);
        if (ec != std::errc() || p != size.data() + size.size() || n.size < 1)
            throw std::invalid_argument(fmt::format("bad size factor '{}' in '{}' (expected NAME:N, N >= 1)", size, text));
    }
    return n;
}

std::string generate_spd(std::string_view name, int size) {
    if (spd_default_size(name) == 0)
        throw std::invalid_argument(fmt::format("unknown scene '{}' (built-in: balls mount rings tetra tree gears)", name));
    if (size == 0) size = spd_default_size(name);
    if (size < 1 || size > 20) throw std::invalid_argument(fmt::format("size factor {} out of range [1, 20]", size));
    NffWriter w;
    if (name == "balls") gen_balls(w, size);
    else if (name == "mount") gen_mount(w, size);
    else if (name == "rings") gen_rings(w, size);
    else if (name == "tetra") gen_tetra(w, size);
    else if (name == "tree") gen_tree(w, size);
    else gen_gears(w, size);
    return w.str();
}

} // namespace nesshi::rt
