// The object file: code as bundles, initialised data, symbols and a line table.
//
// Layout (little-endian; full description in docs/object-format.md):
//   header   "NESSHIO\0" magic, u16 version, u16 reserved, u64 machine fingerprint,
//            u32 machine-name length + bytes, u32 section count
//   sections u32 type, u32 byte length, payload   (CODE, DATA, SYMBOLS, FILES, LINES)
//   trailer  u32 CRC-32 of everything before it
// The reader checks every length, count and index, and the CRC, so a truncated, corrupt or
// foreign file gives a clear error, never a crash.
#pragma once

#include "base/error.hpp"
#include "isa/encoding.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::isa {

inline constexpr uint16_t kObjectVersion = 1;

struct DataSection {
    uint32_t address = 0;
    std::vector<uint8_t> bytes;
    friend bool operator==(const DataSection&, const DataSection&) = default;
};

enum class SymbolKind : uint8_t { Code = 0, Data = 1 };

struct Symbol {
    std::string name;
    SymbolKind kind = SymbolKind::Code;
    uint32_t value = 0; // bundle index (Code) or byte address (Data)
    bool global = false;
    friend bool operator==(const Symbol&, const Symbol&) = default;
};

// Source position of one bundle (for fault reports, traces and the debugger).
struct LineEntry {
    uint32_t file = 0; // index into ObjectFile::files
    uint32_t line = 0;
    friend bool operator==(const LineEntry&, const LineEntry&) = default;
};

struct ObjectFile {
    std::string machine;          // machine description name
    uint64_t machine_fingerprint = 0;
    std::vector<uint64_t> code;   // operation words; kEndOfBundle marks a bundle's last op
    std::vector<DataSection> data;
    std::vector<Symbol> symbols;  // sorted by (kind, value, name)
    std::vector<std::string> files;
    std::vector<LineEntry> lines; // one per bundle, or empty

    size_t bundle_count() const;
    friend bool operator==(const ObjectFile&, const ObjectFile&) = default;
};

class ObjectError : public base::Error {
  public:
    using base::Error::Error;
};

std::vector<uint8_t> write_object(const ObjectFile& obj);
// `name` is used in error messages. Checks structure only; see decode_bundles for code.
ObjectFile read_object(const std::vector<uint8_t>& bytes, std::string_view name);
// Throws ObjectError, also when `path` is not a regular file base::read_file accepts.
ObjectFile read_object_file(const std::string& path);
void write_object_file(const ObjectFile& obj, const std::string& path);

// The code split into bundles of decoded operations. Throws ObjectError naming the first
// illegal word (or a final bundle without its end marker).
std::vector<std::vector<Instr>> decode_bundles(const ObjectFile& obj);

uint32_t crc32(const uint8_t* data, size_t size);

} // namespace nesshi::isa
