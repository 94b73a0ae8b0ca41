// Built-in SPD generators (our own implementations of Haines' Standard Procedural Databases).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::rt {

struct SpdName {
    std::string name; // balls, mount, rings, tetra, tree, gears
    int size = 0;     // size factor (0 = the generator's default)
};

// The paper's five scenes, in its order (gears is built in too: parse_spd_name and generate_spd accept it).
const std::vector<std::string>& spd_names();
int spd_default_size(std::string_view name);
// "balls" -> {balls, default}; "balls:2" -> {balls, 2}; anything else (a path) -> nullopt.
// Throws std::invalid_argument for a known name with a bad size suffix.
std::optional<SpdName> parse_spd_name(std::string_view text);
// The NFF text the generator writes (the SPD default output: curves, 512 x 512 view).
// Throws std::invalid_argument for an unknown name or size out of range.
std::string generate_spd(std::string_view name, int size);

} // namespace nesshi::rt
