// Parser and validator for machine descriptions (TOML), and the built-in presets.
#include "isa/machine.hpp"

#include "isa/encoding.hpp"
#include "isa/identifier.hpp"
#include "machine_presets.hpp" // generated: kPresets[] from isa/machines/*.toml

#include "base/error.hpp"
#include "base/hash.hpp"
#include "base/read_file.hpp"
#include "base/suggest.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <set>

namespace nesshi::isa {

namespace {

struct Ctx {
    std::string source;
    [[noreturn]] void fail(const toml::source_region& where, const std::string& msg) const {
        throw MachineError(base::SourceLoc(source, int(where.begin.line), int(where.begin.column)), msg);
    }
    [[noreturn]] void fail_top(const std::string& msg) const {
        throw MachineError(base::SourceLoc(source, 1, 1), msg);
    }
};

void reject_unknown_keys(const Ctx& ctx, const toml::table& t, std::set<std::string> known,
                         std::string_view where) {
    for (auto&& [k, v] : t)
        if (!known.count(std::string(k.str())))
            ctx.fail(v.source(), fmt::format("unknown key '{}' in {}{}", k.str(), where,
                                             base::did_you_mean(k.str(), {known.begin(), known.end()})));
}

std::vector<std::string> class_names() {
    return {kOpClassNames.begin(), kOpClassNames.end()};
}

uint32_t get_uint(const Ctx& ctx, const toml::table& t, std::string_view key, bool required,
                  uint32_t fallback, uint64_t max, const toml::source_region& parent) {
    const toml::node* n = t.get(key);
    if (!n) {
        if (required) ctx.fail(parent, fmt::format("missing key '{}'", key));
        return fallback;
    }
    auto v = n->value<int64_t>();
    if (!n->is_integer() || !v) ctx.fail(n->source(), fmt::format("'{}' must be an integer", key));
    if (*v < 0 || uint64_t(*v) > max)
        ctx.fail(n->source(), fmt::format("'{}' = {} is out of range 0..{}", key, *v, max));
    return uint32_t(*v);
}

std::string get_string(const Ctx& ctx, const toml::table& t, std::string_view key, bool required,
                       const toml::source_region& parent) {
    const toml::node* n = t.get(key);
    if (!n) {
        if (required) ctx.fail(parent, fmt::format("missing key '{}'", key));
        return {};
    }
    if (!n->is_string()) ctx.fail(n->source(), fmt::format("'{}' must be a string", key));
    return std::string(*n->value<std::string_view>());
}

int class_index(std::string_view name) {
    for (int i = 0; i < kNumOpClasses; ++i)
        if (kOpClassNames[i] == name) return i;
    return -1;
}

// Each parse_* step reads one part of the description into `m`. When `inherited`, `m` starts as
// the parent's copy: an absent table or key keeps the parent's value, and a given array replaces
// the parent's whole array. Without a parent every part is required, as in a flat file.
void parse_regs(const Ctx& ctx, const toml::table& root, Machine& m, bool inherited) {
    const toml::node* rn = root.get("registers");
    if (!rn && inherited) return;
    if (!rn || !rn->is_table()) ctx.fail_top("missing table [registers.int] / [registers.float]");
    const auto& regs = *rn->as_table();
    reject_unknown_keys(ctx, regs, {"int", "float"}, "[registers]");
    const char* names[] = {"int", "float"};
    for (int f = 0; f < kNumRegFiles; ++f) {
        const toml::node* n = regs.get(names[f]);
        if (!n && inherited) continue;
        if (!n || !n->is_table())
            ctx.fail(rn->source(), fmt::format("missing table [registers.{}]", names[f]));
        const auto& t = *n->as_table();
        reject_unknown_keys(ctx, t, {"count", "read_ports", "write_ports"},
                            fmt::format("[registers.{}]", names[f]));
        RegFileDesc& d = m.regs[f];
        d.count = get_uint(ctx, t, "count", !inherited, d.count, kMaxRegs, t.source());
        d.read_ports = get_uint(ctx, t, "read_ports", !inherited, d.read_ports, 64, t.source());
        d.write_ports = get_uint(ctx, t, "write_ports", !inherited, d.write_ports, 64, t.source());
        if (d.count == 0) ctx.fail(t.source(), "a register file needs at least one register");
        if (d.read_ports == 0 || d.write_ports == 0)
            ctx.fail(t.source(), "a register file needs at least one read and one write port");
    }
}

void parse_latency(const Ctx& ctx, const toml::table& root, Machine& m, bool inherited) {
    const toml::node* n = root.get("latency");
    if (!n && inherited) return;
    if (!n || !n->is_table()) ctx.fail_top("missing table [latency]");
    const auto& t = *n->as_table();
    for (auto&& [k, v] : t)
        if (class_index(k.str()) < 0)
            ctx.fail(v.source(), fmt::format("unknown operation class '{}'{}", k.str(), base::did_you_mean(k.str(), class_names())));
    for (int c = 0; c < kNumOpClasses; ++c)
        m.latency[c] =
            get_uint(ctx, t, kOpClassNames[c], !inherited, m.latency[c], 1000, t.source());
    for (int c = 0; c < kNumOpClasses; ++c)
        if (const toml::node* v = t.get(kOpClassNames[c]); v && m.latency[c] == 0)
            ctx.fail(v->source(), "latencies are at least 1 cycle");
}

void parse_slots(const Ctx& ctx, const toml::table& root, Machine& m, bool inherited) {
    const toml::node* n = root.get("slot");
    if (!n && inherited) return;
    if (!n || !n->is_array_of_tables()) ctx.fail_top("missing [[slot]] entries");
    const auto& arr = *n->as_array();
    if (arr.size() > size_t(kMaxSlots))
        ctx.fail(arr.source(), fmt::format("at most {} issue slots", kMaxSlots));
    m.slots.clear();
    for (const auto& e : arr) {
        const auto& t = *e.as_table();
        reject_unknown_keys(ctx, t, {"name", "accepts"}, "[[slot]]");
        SlotDesc s;
        s.name = get_string(ctx, t, "name", true, t.source());
        if (s.name.empty()) ctx.fail(t.source(), "slot name is empty");
        if (!is_slot_name(s.name)) // it prefixes pinned ops (`iu0: add ...`) in sources and disassembly
            ctx.fail(t.get("name")->source(),
                     fmt::format("slot name '{}' is not an identifier (a letter or '_', then letters, digits or '_')",
                                 s.name));
        if (m.slot_index(s.name) >= 0)
            ctx.fail(t.get("name")->source(), fmt::format("duplicate slot name '{}'", s.name));
        const toml::node* acc = t.get("accepts");
        if (!acc || !acc->is_array()) ctx.fail(t.source(), "slot needs 'accepts', a list of classes");
        for (const auto& c : *acc->as_array()) {
            int idx = c.is_string() ? class_index(*c.value<std::string_view>()) : -1;
            if (idx < 0)
                ctx.fail(c.source(),
                         fmt::format("unknown operation class (known: {})",
                                     fmt::join(kOpClassNames.begin(), kOpClassNames.end(), ", ")));
            s.classes |= 1u << idx;
        }
        m.slots.push_back(std::move(s));
    }
    // Every class must be issuable somewhere, or programs using it could never assemble.
    for (int c = 0; c < kNumOpClasses; ++c) {
        bool any = false;
        for (const auto& s : m.slots) any |= s.accepts(OpClass(c));
        if (!any)
            ctx.fail(arr.source(),
                     fmt::format("no slot accepts operation class '{}'", kOpClassNames[c]));
    }
}

void parse_memories(const Ctx& ctx, const toml::table& root, Machine& m, bool inherited) {
    const toml::node* n = root.get("memory");
    if (!n && inherited) return;
    if (!n || !n->is_array_of_tables()) ctx.fail_top("missing [[memory]] entries");
    m.memories.clear();
    for (const auto& e : *n->as_array()) {
        const auto& t = *e.as_table();
        reject_unknown_keys(ctx, t, {"name", "base", "size", "latency", "cached"}, "[[memory]]");
        MemoryDesc d;
        d.name = get_string(ctx, t, "name", true, t.source());
        d.base = get_uint(ctx, t, "base", true, 0, 0xffffffffu, t.source());
        d.size = get_uint(ctx, t, "size", true, 0, 0xffffffffu, t.source());
        d.latency = get_uint(ctx, t, "latency", false, 0, 100000, t.source());
        if (const toml::node* c = t.get("cached")) {
            if (!c->is_boolean()) ctx.fail(c->source(), "'cached' must be true or false");
            d.cached = *c->value<bool>();
        }
        if (d.size == 0 || d.base % 4 || d.size % 4)
            ctx.fail(t.source(), "memory base and size must be multiples of 4, size > 0");
        if (uint64_t{d.base} + d.size > 0x100000000ull)
            ctx.fail(t.source(), "memory extends past the 32-bit address space");
        for (const auto& o : m.memories)
            if (d.base < uint64_t{o.base} + o.size && o.base < uint64_t{d.base} + d.size)
                ctx.fail(t.source(), fmt::format("memory '{}' overlaps '{}'", d.name, o.name));
        m.memories.push_back(std::move(d));
    }
}

// The descriptions being read, outermost first: `identity` detects cycles (a canonical path or
// "builtin:NAME"), `source` names them in the message.
struct Link {
    std::string identity;
    std::string source;
};
using Chain = std::vector<Link>;

// The text of a description file: false when nothing exists at `path`; a path base::read_file
// refuses (a directory, a device, a pipe, a file above kMaxMachineFileBytes) throws MachineError.
bool read_machine_file(const std::string& path, std::string& text) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return false;
    try {
        text = base::read_file(path, base::kMaxMachineFileBytes);
    } catch (const base::Error& e) {
        throw MachineError(e.loc(), e.message());
    }
    return true;
}

// Machine descriptions are about 1 KB and their keys nest two levels ("registers.int"). toml++
// bounds nested values but not the components of one key, and recurses per component, so a
// header or dotted key of tens of thousands of components exhausts the stack: refuse texts that
// are implausibly large, or have a line with more than kMaxDots '.' outside strings and comments,
// before parsing.
constexpr int kMaxDots = 16;

void check_plausible(std::string_view text, std::string_view source) {
    if (text.size() > base::kMaxMachineFileBytes)
        throw MachineError(base::SourceLoc(source, 1, 1), fmt::format("description too large ({} bytes; the limit is {})",
                                                                      text.size(), base::kMaxMachineFileBytes));
    enum class In { Code, Comment, Basic, Literal, MultiBasic, MultiLiteral } in = In::Code;
    int line = 1, dots = 0;
    size_t line_start = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        const char ch = text[i];
        const std::string_view rest = text.substr(i);
        if (ch == '\n') {
            ++line;
            line_start = i + 1;
            dots = 0;
            if (in == In::Comment || in == In::Basic || in == In::Literal) in = In::Code; // one-line forms end
        } else if (in == In::Code) {
            if (ch == '#') {
                in = In::Comment;
            } else if (rest.starts_with(R"(""")")) {
                in = In::MultiBasic;
                i += 2;
            } else if (rest.starts_with("'''")) {
                in = In::MultiLiteral;
                i += 2;
            } else if (ch == '"') {
                in = In::Basic;
            } else if (ch == '\'') {
                in = In::Literal;
            } else if (ch == '.' && ++dots > kMaxDots) {
                throw MachineError(base::SourceLoc(source, line, int(i - line_start + 1)),
                                   fmt::format("more than {} '.' on one line: the keys of a machine description "
                                               "nest a few levels, not this deep", kMaxDots));
            }
        } else if (in == In::Basic || in == In::MultiBasic) {
            if (ch == '\\' && i + 1 < text.size() && text[i + 1] != '\n') ++i; // an escaped character
            else if (in == In::Basic && ch == '"') in = In::Code;
            else if (in == In::MultiBasic && rest.starts_with(R"(""")")) {
                in = In::Code;
                i += 2;
            }
        } else if (in == In::Literal) {
            if (ch == '\'') in = In::Code;
        } else if (in == In::MultiLiteral) {
            if (rest.starts_with("'''")) {
                in = In::Code;
                i += 2;
            }
        }
    }
}

std::string identity_of(std::string_view source) {
    if (source.rfind("builtin:", 0) == 0) return std::string(source);
    std::error_code ec;
    auto canon = std::filesystem::weakly_canonical(std::filesystem::path(source), ec);
    return ec ? std::string(source) : canon.string();
}

Machine parse_in_chain(std::string_view text, std::string_view source, Chain& chain);

// The parent named by `inherits`: a preset, else a file relative to the inheriting file.
Machine parse_parent(const Ctx& ctx, const toml::node& node, Chain& chain) {
    if (!node.is_string()) ctx.fail(node.source(), "'inherits' must be a string");
    const std::string want(*node.value<std::string_view>());
    std::string text, source;
    if (auto preset = preset_text(want); !preset.empty()) {
        text = std::string(preset);
        source = fmt::format("builtin:{}", want);
    } else {
        // A preset cannot reach outside the binary; a file's parent is found beside it.
        namespace fs = std::filesystem;
        const bool builtin = ctx.source.rfind("builtin:", 0) == 0;
        source = (fs::path(ctx.source).parent_path() / fs::path(want)).lexically_normal().string();
        if (want.empty() || builtin || !read_machine_file(source, text))
            ctx.fail(node.source(),
                     fmt::format("unknown parent machine '{}': no such preset{} (presets: {})",
                                 want, builtin ? "" : fmt::format(" or file {}", source),
                                 fmt::join(preset_names(), ", ")));
    }
    const std::string id = identity_of(source);
    for (size_t i = 0; i < chain.size(); ++i)
        if (chain[i].identity == id) {
            std::vector<std::string_view> names;
            for (size_t j = i; j < chain.size(); ++j) names.push_back(chain[j].source);
            names.push_back(source);
            ctx.fail(node.source(), fmt::format("machine inheritance cycle: {}",
                                                fmt::join(names, " -> ")));
        }
    if (chain.size() > size_t(kMaxInheritDepth))
        ctx.fail(node.source(), fmt::format("machine inheritance deeper than {} levels",
                                            kMaxInheritDepth));
    return parse_in_chain(text, source, chain);
}

Machine parse_in_chain(std::string_view text, std::string_view source, Chain& chain) {
    Ctx ctx{std::string(source)};
    check_plausible(text, source);
    toml::table root;
    try {
        root = toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        ctx.fail(e.source(), std::string(e.description()));
    }
    reject_unknown_keys(ctx, root,
                        {"name", "description", "inherits", "branch_penalty", "registers",
                         "latency", "slot", "memory"},
                        "the top level");
    Machine m;
    const toml::node* parent = root.get("inherits");
    if (parent) {
        chain.push_back({identity_of(source), std::string(source)});
        m = parse_parent(ctx, *parent, chain);
        chain.pop_back();
    }
    const bool inherited = parent != nullptr;
    // name and description name this machine, not its parent: never inherited.
    m.source = std::string(source);
    m.name = get_string(ctx, root, "name", true, root.source());
    m.description = get_string(ctx, root, "description", false, root.source());
    if (m.name.empty()) ctx.fail_top("machine name is empty");
    m.branch_penalty =
        get_uint(ctx, root, "branch_penalty", false, m.branch_penalty, 1000, root.source());
    parse_regs(ctx, root, m, inherited);
    parse_latency(ctx, root, m, inherited);
    parse_slots(ctx, root, m, inherited);
    parse_memories(ctx, root, m, inherited);
    return m;
}

} // namespace

Machine parse_machine(std::string_view text, std::string_view source) {
    Chain chain;
    return parse_in_chain(text, source, chain);
}

const MemoryDesc* Machine::memory_at(uint32_t addr, uint32_t bytes) const {
    for (const auto& d : memories)
        if (d.contains(addr, bytes)) return &d;
    return nullptr;
}

int Machine::slot_index(std::string_view slot_name) const {
    for (size_t i = 0; i < slots.size(); ++i)
        if (slots[i].name == slot_name) return int(i);
    return -1;
}

std::string Machine::reference() const {
    constexpr std::string_view builtin = "builtin:";
    return source.rfind(builtin, 0) == 0 ? source.substr(builtin.size()) : source;
}

uint32_t Machine::max_latency() const {
    uint32_t m = 1;
    for (auto l : latency) m = std::max(m, l);
    return m;
}

uint64_t Machine::fingerprint() const {
    // FNV-1a over a canonical rendering of everything that matters to assembly and timing.
    std::string s = fmt::format("{}|bp{}|", name, branch_penalty);
    for (const auto& sl : slots) s += fmt::format("{}:{};", sl.name, sl.classes);
    for (auto l : latency) s += fmt::format("{},", l);
    for (const auto& r : regs) s += fmt::format("r{}/{}/{};", r.count, r.read_ports, r.write_ports);
    for (const auto& d : memories)
        s += fmt::format("{}@{}+{}l{}c{};", d.name, d.base, d.size, d.latency, d.cached);
    return base::fnv1a64(s);
}

bool Machine::same_as(const Machine& other) const {
    Machine renamed = other;
    renamed.name = name;
    return renamed.fingerprint() == fingerprint();
}

bool is_preset(std::string_view name) { return !preset_text(name).empty(); }

std::vector<std::string_view> preset_names() {
    std::vector<std::string_view> v;
    for (const auto& p : kPresets) v.push_back(p.name);
    std::sort(v.begin(), v.end());
    return v;
}

std::string_view preset_text(std::string_view name) {
    for (const auto& p : kPresets)
        if (p.name == name) return p.text;
    return {};
}

Machine load_machine(std::string_view name_or_path) {
    if (auto text = preset_text(name_or_path); !text.empty())
        return parse_machine(text, fmt::format("builtin:{}", name_or_path));
    std::string text;
    if (!read_machine_file(std::string(name_or_path), text))
        throw MachineError(base::SourceLoc(name_or_path), fmt::format("no such machine preset or file (presets: {})",
                                                                      fmt::join(preset_names(), ", ")));
    return parse_machine(text, name_or_path);
}

} // namespace nesshi::isa
