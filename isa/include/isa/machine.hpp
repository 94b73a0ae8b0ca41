// Machine descriptions: issue slots, latencies, register-file ports and memories, as data.
//
// Built-in presets (os, ic, seq and their -real variants) are embedded copies of
// isa/machines/*.toml; users load their own with `-m PATH`. Both go through one parser that
// reports `file:line:col: error:` for anything malformed or inconsistent. A description may
// start from another (`inherits = "os"`) and list only its differences.
#pragma once

#include "base/error.hpp"
#include "isa/ops.hpp"

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::isa {

struct SlotDesc {
    std::string name;
    uint32_t classes = 0; // bit i set: accepts OpClass(i)
    bool accepts(OpClass c) const { return (classes >> static_cast<int>(c)) & 1u; }
    bool operator==(const SlotDesc&) const = default;
};

struct RegFileDesc {
    uint32_t count = 128;
    uint32_t read_ports = 1;
    uint32_t write_ports = 1;
    bool operator==(const RegFileDesc&) const = default;
};

struct MemoryDesc {
    std::string name;
    uint32_t base = 0;
    uint32_t size = 0;
    uint32_t latency = 0; // extra stall cycles per access beyond the load class latency
    bool cached = false;  // reached through the cache (ideal: always hits)
    bool contains(uint32_t addr, uint32_t bytes) const {
        return addr >= base && uint64_t{addr} + bytes <= uint64_t{base} + size;
    }
    bool operator==(const MemoryDesc&) const = default;
};

struct Machine {
    std::string name;
    std::string description;
    std::string source; // "builtin:os" or the file it was read from
    std::vector<SlotDesc> slots;
    std::array<uint32_t, kNumOpClasses> latency{};
    std::array<RegFileDesc, kNumRegFiles> regs{};
    std::vector<MemoryDesc> memories;
    uint32_t branch_penalty = 0; // extra cycles after a taken branch

    uint32_t latency_of(const OpInfo& op) const { return latency[static_cast<int>(op.cls)]; }
    const RegFileDesc& regfile(RegFile rf) const { return regs[static_cast<int>(rf)]; }
    const MemoryDesc* memory_at(uint32_t addr, uint32_t bytes) const;
    int slot_index(std::string_view slot_name) const; // -1 when absent
    uint32_t max_latency() const;
    // What load_machine takes to give this machine back: the preset's name, else its file (a
    // `# machine:` line names it so).
    std::string reference() const;
    // A hash of everything that affects assembly or timing, and the name; objects record it.
    uint64_t fingerprint() const;
    // The same machine under any name: equal fingerprints once the names are equal (a file that
    // only inherits a preset is that preset, and gets its kernels).
    bool same_as(const Machine& other) const;
    // Every field, source and description included (compare fingerprints to ignore those).
    bool operator==(const Machine&) const = default;
};

// A malformed description; what() is `file:line:col: error: message`.
class MachineError : public base::Error {
  public:
    using base::Error::Error;
};

// How many ancestors a description may have through `inherits` (a parent that inherits in turn
// is a second level, and so on).
inline constexpr int kMaxInheritDepth = 8;

// Parses a description; `source` names it in error messages, and a file named by `inherits` is
// found relative to the directory of `source` (docs/isa.md gives the merge rules).
Machine parse_machine(std::string_view toml_text, std::string_view source);
// A preset name (os, ic, seq, os-real, ic-real, seq-real) or a path to a .toml file.
Machine load_machine(std::string_view name_or_path);
bool is_preset(std::string_view name);
std::vector<std::string_view> preset_names();
std::string_view preset_text(std::string_view name); // empty when absent

} // namespace nesshi::isa
