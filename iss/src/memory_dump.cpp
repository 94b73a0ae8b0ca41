// Memory dumps by label and their comparison with expected values.
#include "iss/memory_dump.hpp"

#include "base/error.hpp"

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace nesshi::iss {

namespace {

bool parse_u32(std::string_view s, std::uint32_t& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size() && !s.empty();
}

bool parse_format(std::string_view s, DumpFormat& f) {
    if (s == "f32") f = DumpFormat::f32;
    else if (s == "i32") f = DumpFormat::i32;
    else if (s == "hex") f = DumpFormat::hex;
    else return false;
    return true;
}

const char* format_name(DumpFormat f) {
    switch (f) {
    case DumpFormat::f32: return "f32";
    case DumpFormat::i32: return "i32";
    case DumpFormat::hex: return "hex";
    }
    return "?";
}

std::string show(std::uint32_t w, DumpFormat f) {
    switch (f) {
    case DumpFormat::f32: return fmt::format("{}", std::bit_cast<float>(w));
    case DumpFormat::i32: return fmt::format("{}", static_cast<std::int32_t>(w));
    case DumpFormat::hex: return fmt::format("0x{:08x}", w);
    }
    return "?";
}

} // namespace

DumpSpec parse_dump_spec(std::string_view spec) {
    DumpSpec d;
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
        const std::size_t colon = spec.find(':', start);
        parts.push_back(spec.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
        if (colon == std::string_view::npos) break;
        start = colon + 1;
    }
    if (parts[0].empty() || parts.size() > 3)
        throw std::invalid_argument(fmt::format("bad dump spec '{}' (expected LABEL[:COUNT][:f32|i32|hex])", spec));
    d.label = std::string(parts[0]);
    for (std::size_t i = 1; i < parts.size(); ++i) {
        std::uint32_t n = 0;
        if (i == 1 && parse_u32(parts[i], n)) {
            if (n == 0) throw std::invalid_argument(fmt::format("bad dump spec '{}': the count must be at least 1", spec));
            d.count = n;
        } else if (!parse_format(parts[i], d.format) || (i == 1 && parts.size() == 3)) {
            throw std::invalid_argument(fmt::format(
                "bad dump spec '{}': '{}' is neither a word count nor a format (f32, i32, hex)", spec, parts[i]));
        }
    }
    return d;
}

std::uint32_t default_dump_words(const Program& prog, std::uint32_t address) {
    for (const isa::DataSection& s : prog.object().data) {
        const std::uint64_t end = std::uint64_t{s.address} + s.bytes.size();
        if (address < s.address || address >= end) continue;
        std::uint64_t stop = end;
        for (const isa::Symbol& sym : prog.object().symbols)
            if (sym.kind == isa::SymbolKind::Data && sym.value > address && sym.value < stop) stop = sym.value;
        return static_cast<std::uint32_t>(std::max<std::uint64_t>(1, (stop - address + 3) / 4));
    }
    return 1;
}

MemoryDump dump_memory(const Processor& p, const DumpSpec& spec) {
    const Program& prog = p.program();
    const isa::Symbol* sym = prog.find_symbol(spec.label);
    if (!sym) throw std::invalid_argument(fmt::format("no label '{}' in the program", spec.label));
    if (sym->kind != isa::SymbolKind::Data)
        throw std::invalid_argument(fmt::format("'{}' is a code label; --dump and --expect take data labels", spec.label));
    MemoryDump d;
    d.label = spec.label;
    d.address = sym->value;
    d.format = spec.format;
    const std::uint32_t n = spec.count ? *spec.count : default_dump_words(prog, d.address);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint64_t a = std::uint64_t{d.address} + 4ull * i;
        std::uint32_t w = 0;
        if (a > std::numeric_limits<std::uint32_t>::max() || !p.memory().peek(static_cast<std::uint32_t>(a), 4, w))
            throw std::invalid_argument(fmt::format("{}[{}] (0x{:x}) is outside the memories of machine {}", spec.label, i,
                                                    a, prog.machine().name));
        d.words.push_back(w);
    }
    return d;
}

std::string MemoryDump::text() const {
    std::string o = fmt::format("{} @ 0x{:08x}: {} x {}\n", label, address, words.size(), format_name(format));
    for (std::size_t i = 0; i < words.size(); i += 8) {
        o += fmt::format("  [{}]", i);
        for (std::size_t k = i; k < std::min(words.size(), i + 8); ++k) o += " " + show(words[k], format);
        o += "\n";
    }
    return o;
}

std::vector<Expected> parse_values(std::string_view text, std::string_view file, DumpFormat format) {
    std::vector<Expected> out;
    int line = 1;
    std::size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (c == '#') {
            while (i < text.size() && text[i] != '\n') ++i;
            continue;
        }
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',') {
            ++i;
            continue;
        }
        std::size_t j = i;
        while (j < text.size() && std::string_view(" \t\r\n,#").find(text[j]) == std::string_view::npos) ++j;
        const std::string tok(text.substr(i, j - i));
        Expected e;
        e.text = tok;
        bool ok = false;
        if (format == DumpFormat::f32) {
            char* end = nullptr;
            const float f = std::strtof(tok.c_str(), &end);
            ok = end == tok.c_str() + tok.size();
            e.bits = std::bit_cast<std::uint32_t>(f);
            e.is_nan = std::isnan(f);
        } else {
            char* end = nullptr;
            const long long v = std::strtoll(tok.c_str(), &end, 0);
            ok = end == tok.c_str() + tok.size() && v >= std::numeric_limits<std::int32_t>::min() &&
                 v <= std::numeric_limits<std::uint32_t>::max();
            e.bits = static_cast<std::uint32_t>(v);
        }
        if (!ok)
            throw base::Error(base::SourceLoc(file, line), fmt::format("'{}' is not a{} value", tok,
                                                                     format == DumpFormat::f32 ? " float" : "n integer"));
        out.push_back(std::move(e));
        i = j;
    }
    return out;
}

std::uint64_t ulp_distance(std::uint32_t a, std::uint32_t b) {
    // Map the sign-magnitude patterns onto one monotonic integer line (-0 just below +0).
    auto line = [](std::uint32_t x) -> std::int64_t {
        return (x & 0x80000000u) ? -static_cast<std::int64_t>(x & 0x7fffffffu) - 1 : static_cast<std::int64_t>(x);
    };
    const std::int64_t d = line(a) - line(b);
    return static_cast<std::uint64_t>(d < 0 ? -d : d);
}

Mismatch compare(const MemoryDump& d, const std::vector<Expected>& want, std::uint64_t max_ulp) {
    Mismatch m;
    if (want.size() != d.words.size()) {
        m.found = true;
        m.index = std::min(want.size(), d.words.size());
        m.message = fmt::format("{}: the file holds {} values, the dump {} words", d.label, want.size(), d.words.size());
        return m;
    }
    for (std::size_t i = 0; i < want.size(); ++i) {
        const std::uint32_t got = d.words[i];
        const Expected& e = want[i];
        bool same = got == e.bits;
        std::string how;
        if (d.format == DumpFormat::f32) {
            const bool got_nan = std::isnan(std::bit_cast<float>(got));
            const std::uint64_t ulps = ulp_distance(got, e.bits);
            same = (got_nan && e.is_nan) || (!got_nan && !e.is_nan && ulps <= max_ulp);
            how = got_nan || e.is_nan ? "" : fmt::format(": {} ulp apart", ulps);
        }
        if (same) continue;
        m.found = true;
        m.index = i;
        m.message = fmt::format("{}[{}] (0x{:08x}): expected {} (0x{:08x}), got {} (0x{:08x}){}", d.label, i,
                                d.address + 4 * i, e.text, e.bits, show(got, d.format), got, how);
        return m;
    }
    return m;
}

} // namespace nesshi::iss
