// Object file writer and defensive reader.
#include "isa/object.hpp"

#include "base/error.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "isa/identifier.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <iterator>

namespace nesshi::isa {

namespace {

// `s` with every byte outside printable ASCII as \xNN, for a message about a bad name.
std::string printable(std::string_view s) {
    std::string out;
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7f) out += c;
        else out += fmt::format("\\x{:02x}", u);
    }
    return out;
}

constexpr char kMagic[8] = {'N', 'E', 'S', 'S', 'H', 'I', 'O', '\0'};
enum SectionType : uint32_t { kCode = 1, kData = 2, kSymbols = 3, kFiles = 4, kLines = 5 };
constexpr uint32_t kMaxName = 4096;

class Writer {
  public:
    std::vector<uint8_t> out;
    void u8(uint8_t v) { out.push_back(v); }
    void u16(uint16_t v) { for (int i = 0; i < 2; ++i) out.push_back(uint8_t(v >> (8 * i))); }
    void u32(uint32_t v) { for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i))); }
    void u64(uint64_t v) { for (int i = 0; i < 8; ++i) out.push_back(uint8_t(v >> (8 * i))); }
    void str(std::string_view s) {
        u32(uint32_t(s.size()));
        out.insert(out.end(), s.begin(), s.end());
    }
    void bytes(const std::vector<uint8_t>& b) { out.insert(out.end(), b.begin(), b.end()); }
};

class Reader {
  public:
    Reader(const uint8_t* p, size_t n, std::string_view name, std::string_view what)
        : p_(p), n_(n), name_(name), what_(what) {}
    [[noreturn]] void fail(std::string_view msg) const {
        throw ObjectError(base::SourceLoc(name_), fmt::format("{} (in {} at byte {})", msg, what_, pos_));
    }
    void need(size_t k) const {
        if (n_ - pos_ < k) fail("truncated");
    }
    uint8_t u8() { need(1); return p_[pos_++]; }
    uint16_t u16() { need(2); uint16_t v = uint16_t(p_[pos_] | p_[pos_ + 1] << 8); pos_ += 2; return v; }
    uint32_t u32() {
        need(4);
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= uint32_t(p_[pos_ + i]) << (8 * i);
        pos_ += 4;
        return v;
    }
    uint64_t u64() { uint64_t lo = u32(); return lo | uint64_t(u32()) << 32; }
    std::string str() {
        uint32_t len = u32();
        if (len > kMaxName) fail(fmt::format("string length {} is implausible", len));
        need(len);
        std::string s(reinterpret_cast<const char*>(p_ + pos_), len);
        pos_ += len;
        return s;
    }
    std::vector<uint8_t> bytes(size_t k) {
        need(k);
        std::vector<uint8_t> v(p_ + pos_, p_ + pos_ + k);
        pos_ += k;
        return v;
    }
    bool done() const { return pos_ == n_; }
    size_t pos() const { return pos_; }

  private:
    const uint8_t* p_;
    size_t n_;
    size_t pos_ = 0;
    std::string_view name_, what_;
};

void section(Writer& w, uint32_t type, const Writer& body) {
    w.u32(type);
    w.u32(uint32_t(body.out.size()));
    w.bytes(body.out);
}

} // namespace

uint32_t crc32(const uint8_t* data, size_t size) {
    static const auto table = [] {
        std::array<uint32_t, 256> t{};
        for (uint32_t i = 0; i < 256; ++i) {
            uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}

size_t ObjectFile::bundle_count() const {
    return size_t(std::count_if(code.begin(), code.end(),
                                [](uint64_t w) { return (w & kEndOfBundle) != 0; }));
}

std::vector<uint8_t> write_object(const ObjectFile& obj) {
    Writer w;
    w.out.insert(w.out.end(), std::begin(kMagic), std::end(kMagic));
    w.u16(kObjectVersion);
    w.u16(0);
    w.u64(obj.machine_fingerprint);
    w.str(obj.machine);
    w.u32(5);
    Writer code;
    for (uint64_t word : obj.code) code.u64(word);
    section(w, kCode, code);
    Writer data;
    data.u32(uint32_t(obj.data.size()));
    for (const auto& d : obj.data) {
        data.u32(d.address);
        data.u32(uint32_t(d.bytes.size()));
        data.bytes(d.bytes);
    }
    section(w, kData, data);
    Writer syms;
    syms.u32(uint32_t(obj.symbols.size()));
    for (const auto& s : obj.symbols) {
        syms.str(s.name);
        syms.u8(uint8_t(s.kind));
        syms.u8(s.global ? 1 : 0);
        syms.u32(s.value);
    }
    section(w, kSymbols, syms);
    Writer files;
    files.u32(uint32_t(obj.files.size()));
    for (const auto& f : obj.files) files.str(f);
    section(w, kFiles, files);
    Writer lines;
    lines.u32(uint32_t(obj.lines.size()));
    for (const auto& l : obj.lines) {
        lines.u32(l.file);
        lines.u32(l.line);
    }
    section(w, kLines, lines);
    w.u32(crc32(w.out.data(), w.out.size()));
    return w.out;
}

ObjectFile read_object(const std::vector<uint8_t>& bytes, std::string_view name) {
    Reader hdr(bytes.data(), bytes.size(), name, "header");
    if (bytes.size() < sizeof kMagic || !std::equal(std::begin(kMagic), std::end(kMagic), bytes.begin()))
        throw ObjectError(base::SourceLoc(name), "not a Nesshisen object file (bad magic)");
    if (bytes.size() < sizeof kMagic + 4)
        throw ObjectError(base::SourceLoc(name), "truncated object file");
    uint32_t stored = 0;
    for (int i = 0; i < 4; ++i) stored |= uint32_t(bytes[bytes.size() - 4 + i]) << (8 * i);
    ObjectFile obj;
    hdr.bytes(sizeof kMagic);
    uint16_t version = hdr.u16();
    if (version != kObjectVersion)
        throw ObjectError(base::SourceLoc(name), fmt::format("object format version {} (this tool reads {})", version, kObjectVersion));
    if (stored != crc32(bytes.data(), bytes.size() - 4))
        throw ObjectError(base::SourceLoc(name), "checksum mismatch: the file is corrupt or truncated");
    Reader r(bytes.data(), bytes.size() - 4, name, "header");
    r.bytes(sizeof kMagic + 2);
    if (r.u16() != 0) r.fail("reserved header field is not zero");
    obj.machine_fingerprint = r.u64();
    obj.machine = r.str();
    uint32_t nsec = r.u32();
    if (nsec != 5) r.fail(fmt::format("expected 5 sections, found {}", nsec));
    for (uint32_t expect = kCode; expect <= kLines; ++expect) {
        uint32_t type = r.u32();
        uint32_t len = r.u32();
        if (type != expect) r.fail(fmt::format("section {} where {} was expected", type, expect));
        auto body = r.bytes(len);
        static constexpr const char* names[] = {"", "code section", "data section",
                                                "symbol section", "file section", "line section"};
        Reader s(body.data(), body.size(), name, names[type]);
        switch (type) {
        case kCode:
            if (len % 8) s.fail("code size is not a multiple of 8 bytes");
            for (uint32_t i = 0; i < len / 8; ++i) obj.code.push_back(s.u64());
            break;
        case kData: {
            uint32_t n = s.u32();
            if (n > len) s.fail("implausible data section count");
            for (uint32_t i = 0; i < n; ++i) {
                DataSection d;
                d.address = s.u32();
                uint32_t sz = s.u32();
                d.bytes = s.bytes(sz);
                if (uint64_t{d.address} + sz > 0x100000000ull) s.fail("data past the address space");
                obj.data.push_back(std::move(d));
            }
            break;
        }
        case kSymbols: {
            uint32_t n = s.u32();
            if (n > len) s.fail("implausible symbol count");
            for (uint32_t i = 0; i < n; ++i) {
                Symbol sym;
                sym.name = s.str();
                uint8_t kind = s.u8();
                uint8_t global = s.u8();
                if (kind > 1 || global > 1) s.fail("bad symbol kind or flag");
                sym.kind = SymbolKind(kind);
                sym.global = global != 0;
                sym.value = s.u32();
                if (sym.name.empty()) s.fail("empty symbol name");
                if (!is_identifier(sym.name)) // printed by dis and in --stats-json: it must be a name
                    s.fail(fmt::format("symbol name '{}' is not an identifier ([A-Za-z_.$][A-Za-z0-9_.$]*)",
                                       printable(sym.name)));
                obj.symbols.push_back(std::move(sym));
            }
            break;
        }
        case kFiles: {
            uint32_t n = s.u32();
            if (n > len) s.fail("implausible file count");
            for (uint32_t i = 0; i < n; ++i) obj.files.push_back(s.str());
            break;
        }
        case kLines: {
            uint32_t n = s.u32();
            if (n > len) s.fail("implausible line-table size");
            for (uint32_t i = 0; i < n; ++i) {
                LineEntry l;
                l.file = s.u32();
                l.line = s.u32();
                if (l.file >= obj.files.size()) s.fail("line entry names a missing file");
                obj.lines.push_back(l);
            }
            break;
        }
        }
        if (!s.done()) s.fail("trailing bytes in section");
    }
    if (!r.done()) r.fail("trailing bytes after the last section");
    size_t bundles = obj.bundle_count();
    if (!obj.lines.empty() && obj.lines.size() != bundles)
        r.fail(fmt::format("line table has {} entries for {} bundles", obj.lines.size(), bundles));
    for (const auto& sym : obj.symbols)
        if (sym.kind == SymbolKind::Code && sym.value > bundles)
            r.fail(fmt::format("code symbol '{}' points past the end of the code", sym.name));
    return obj;
}

ObjectFile read_object_file(const std::string& path) {
    std::string text;
    try {
        text = base::read_file(path);
    } catch (const base::Error& e) {
        throw ObjectError(e.loc(), e.message());
    }
    return read_object(std::vector<uint8_t>(text.begin(), text.end()), path);
}

void write_object_file(const ObjectFile& obj, const std::string& path) {
    const auto bytes = write_object(obj);
    base::write_file(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::vector<std::vector<Instr>> decode_bundles(const ObjectFile& obj) {
    std::vector<std::vector<Instr>> bundles;
    std::vector<Instr> cur;
    for (size_t i = 0; i < obj.code.size(); ++i) {
        DecodeResult d = decode(obj.code[i]);
        if (!d.ok)
            throw ObjectError(fmt::format("illegal encoding 0x{:016x} at word {} (bundle {}): {}",
                                          obj.code[i], i, bundles.size(), d.error));
        cur.push_back(d.instr);
        if (d.end_of_bundle) {
            bundles.push_back(std::move(cur));
            cur.clear();
        }
    }
    if (!cur.empty())
        throw ObjectError(fmt::format("the last bundle ({}) has no end-of-bundle marker", bundles.size()));
    return bundles;
}

} // namespace nesshi::isa
