// Memory after a run, by data label: `nesshi sim --dump LABEL[:COUNT][:f32|i32|hex]` prints it and
// `--expect LABEL[:COUNT][:FORMAT]=FILE [--ulp N]` compares it with a file of values, so checking a
// loop's results is a command, not a scrape of the debugger's output.
//
//   const iss::DumpSpec spec = iss::parse_dump_spec("ys:8:f32");
//   const iss::MemoryDump d = iss::dump_memory(proc, spec);        // d.text(): "ys @ 0x1020: 8 x f32 ..."
//   const iss::Mismatch m = iss::compare(d, iss::parse_values(text, "ys.txt"), 0);
//   if (m) fmt::print("{}", m.message);
#pragma once

#include "iss/processor.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::iss {

// f32 prints each word as the shortest decimal that reads back to the same binary32 (the
// default: the loops one checks are mostly floating point); i32 as a signed integer; hex as 0x%08x.
enum class DumpFormat : std::uint8_t { f32, i32, hex };

struct DumpSpec {
    std::string label;
    std::optional<std::uint32_t> count; // words; default: up to the next data label or the end of its section
    DumpFormat format = DumpFormat::f32;
};
// "ys", "ys:8", "ys:hex", "ys:8:i32". Throws std::invalid_argument with a message naming the spec.
DumpSpec parse_dump_spec(std::string_view spec);

struct MemoryDump {
    std::string label;
    std::uint32_t address = 0;
    DumpFormat format = DumpFormat::f32;
    std::vector<std::uint32_t> words;
    std::string text() const; // a header line, then 8 values per line, each line led by its index
};
// Reads the words at `spec.label` from the processor's memory. Throws std::invalid_argument for
// an unknown or code label, or a range outside the machine's memories.
MemoryDump dump_memory(const Processor& p, const DumpSpec& spec);
// The default word count of a data label: up to the next data label in its section, or the
// section's end (1 when the label lies outside every initialised section).
std::uint32_t default_dump_words(const Program& prog, std::uint32_t address);

// One expected value: the text as written (for messages) and its 32-bit pattern under a format.
struct Expected {
    std::string text;
    std::uint32_t bits = 0;
    bool is_nan = false; // f32: any NaN matches any NaN
};
// Values separated by whitespace or commas, `#` comments to the end of a line. f32 takes decimal
// floats (`1.5`, `-2e-3`, `inf`, `nan`); i32 and hex take decimal or 0x integers. Throws
// base::Error at FILE:LINE on a value that does not parse.
std::vector<Expected> parse_values(std::string_view text, std::string_view file, DumpFormat format);

// Distance in units in the last place between two binary32 patterns (0 for equal, +0 and -0 are 1 apart).
std::uint64_t ulp_distance(std::uint32_t a, std::uint32_t b);

struct Mismatch {
    bool found = false;
    std::size_t index = 0;
    std::string message; // "ys[3]: expected 1.5 (0x3fc00000), got 1.5000001 (0x3fc00001): 1 ulp apart"
    explicit operator bool() const { return found; }
};
// The first word of `d` that differs from `want` (f32: by more than `max_ulp` ulps), or a count
// mismatch. An empty Mismatch when all agree.
Mismatch compare(const MemoryDump& d, const std::vector<Expected>& want, std::uint64_t max_ulp);

} // namespace nesshi::iss
