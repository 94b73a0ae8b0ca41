// Resource checks on one bundle, and slot assignment (see bundle_check.hpp).
#include "isa/bundle_check.hpp"

#include <fmt/core.h>

#include <array>

namespace nesshi::isa {

std::string_view rule_name(Rule r) {
    switch (r) {
    case Rule::SlotRange: return "slot-range";
    case Rule::SlotClass: return "slot-class";
    case Rule::SlotTwice: return "slot-twice";
    case Rule::RegRange: return "reg-range";
    case Rule::ReadPorts: return "read-ports";
    case Rule::WritePorts: return "write-ports";
    case Rule::DupWrite: return "dup-write";
    }
    return "?";
}

namespace {

char file_prefix(RegFile f) { return f == RegFile::Int ? 'r' : 'f'; }

void check_slots(const Machine& m, std::span<const Instr> ops, std::vector<Violation>& out) {
    std::array<int, kMaxSlots> owner;
    owner.fill(-1);
    for (int i = 0; i < int(ops.size()); ++i) {
        const Instr& in = ops[i];
        if (in.slot >= m.slots.size()) {
            out.push_back({Rule::SlotRange, i, -1,
                           fmt::format("slot {} does not exist on {} ({} slots)", in.slot, m.name,
                                       m.slots.size()), {}});
            continue;
        }
        const SlotDesc& s = m.slots[in.slot];
        if (!s.accepts(in.info().cls))
            out.push_back({Rule::SlotClass, i, -1,
                           fmt::format("slot {} does not accept '{}' (class {})", s.name,
                                       in.info().mnemonic, kOpClassNames[int(in.info().cls)]), {}});
        if (owner[in.slot] >= 0)
            out.push_back({Rule::SlotTwice, i, owner[in.slot],
                           fmt::format("slot {} is already used in this bundle", s.name),
                           fmt::format("slot {} taken by '{}'", s.name,
                                       ops[owner[in.slot]].info().mnemonic)});
        else
            owner[in.slot] = i;
    }
}

void check_registers(const Machine& m, std::span<const Instr> ops, std::vector<Violation>& out) {
    // Reads, all at issue.
    std::array<uint32_t, kNumRegFiles> reads{};
    std::array<int, kNumRegFiles> first_reader{-1, -1};
    // Writes, keyed by landing cycle (latency).
    struct Write { RegFile file; uint8_t reg; uint32_t lat; int op; };
    std::vector<Write> writes;
    bool read_reported[kNumRegFiles] = {false, false};
    for (int i = 0; i < int(ops.size()); ++i) {
        const Instr& in = ops[i];
        uint32_t lat = m.latency_of(in.info());
        for (const RegOperand& r : register_operands(in)) {
            const RegFileDesc& rf = m.regfile(r.file);
            int f = int(r.file);
            if (r.reg >= rf.count)
                out.push_back({Rule::RegRange, i, -1,
                               fmt::format("register {}{} out of range: {} has {} registers",
                                           file_prefix(r.file), r.reg, m.name, rf.count), {}});
            if (r.write) {
                writes.push_back({r.file, r.reg, lat, i});
                continue;
            }
            if (first_reader[f] < 0) first_reader[f] = i;
            if (++reads[f] > rf.read_ports && !read_reported[f]) {
                read_reported[f] = true;
                uint32_t total = 0;
                for (const Instr& o : ops) total += port_use(o.info()).reads[f];
                out.push_back({Rule::ReadPorts, i, first_reader[f] == i ? -1 : first_reader[f],
                               fmt::format("bundle needs {} {} read ports; {} has {}", total,
                                           kRegFileNames[f], m.name, rf.read_ports),
                               fmt::format("first {} read of the bundle", kRegFileNames[f])});
            }
        }
    }
    // Writes landing in the same cycle: port count and duplicate registers.
    for (size_t a = 0; a < writes.size(); ++a) {
        const Write& w = writes[a];
        uint32_t same_cycle = 0;
        int first = -1;
        for (size_t b = 0; b < a; ++b) {
            const Write& o = writes[b];
            if (o.file != w.file || o.lat != w.lat) continue;
            if (first < 0) first = o.op;
            ++same_cycle;
            if (o.reg == w.reg)
                out.push_back({Rule::DupWrite, w.op, o.op,
                               fmt::format("{}{} is written twice in cycle +{}", file_prefix(w.file),
                                           w.reg, w.lat),
                               fmt::format("other write of {}{}", file_prefix(w.file), w.reg)});
        }
        const RegFileDesc& rf = m.regfile(w.file);
        if (same_cycle + 1 == rf.write_ports + 1)
            out.push_back({Rule::WritePorts, w.op, first,
                           fmt::format("bundle needs more than {} {} write ports in cycle +{}; {} "
                                       "has {}", rf.write_ports, kRegFileNames[int(w.file)], w.lat,
                                       m.name, rf.write_ports),
                           fmt::format("first {} write landing in cycle +{}",
                                       kRegFileNames[int(w.file)], w.lat)});
    }
}

} // namespace

std::vector<Violation> check_bundle(const Machine& m, std::span<const Instr> ops) {
    std::vector<Violation> out;
    check_slots(m, ops, out);
    check_registers(m, ops, out);
    return out;
}

bool bundle_fits(const Machine& m, std::span<const Instr> ops) {
    std::array<bool, kMaxSlots> taken{};
    std::array<uint32_t, kNumRegFiles> reads{};
    struct Write { RegFile file; uint8_t reg; uint32_t lat; };
    std::array<Write, 4 * kMaxSlots> writes; // each op passing the slot checks writes at most 4
    std::size_t nwrites = 0;
    for (const Instr& in : ops) {
        if (in.slot >= m.slots.size() || !m.slots[in.slot].accepts(in.info().cls) || taken[in.slot]) return false;
        taken[in.slot] = true;
        const uint32_t lat = m.latency_of(in.info());
        const RegOperands regs = register_operands(in);
        for (const RegOperand& r : regs) {
            const RegFileDesc& rf = m.regfile(r.file);
            if (r.reg >= rf.count) return false;
            if (!r.write) {
                if (++reads[int(r.file)] > rf.read_ports) return false;
                continue;
            }
            uint32_t same_cycle = 1;
            for (std::size_t b = 0; b < nwrites; ++b) {
                const Write& o = writes[b];
                if (o.file != r.file || o.lat != lat) continue;
                if (o.reg == r.reg || ++same_cycle > rf.write_ports) return false;
            }
            writes[nwrites++] = {r.file, r.reg, lat};
        }
    }
    return true;
}

bool assign_slots(const Machine& m, std::span<Instr> ops, std::span<const int> pinned) {
    const int nslots = int(m.slots.size());
    std::array<int, kMaxSlots> owner;
    owner.fill(-1);
    for (size_t i = 0; i < ops.size(); ++i) {
        if (pinned[i] < 0) continue;
        if (pinned[i] >= nslots || owner[pinned[i]] >= 0) return false;
        owner[pinned[i]] = int(i);
        ops[i].slot = uint8_t(pinned[i]);
    }
    // Kuhn's augmenting paths; at most 8 x 8, so this is trivially cheap. A free slot that
    // accepts the op is taken first, so ops only move when they must (readable placements).
    auto place = [&](auto& self, int i, std::array<bool, kMaxSlots>& seen) -> bool {
        for (int s = 0; s < nslots; ++s)
            if (owner[s] < 0 && !seen[s] && m.slots[s].accepts(ops[i].info().cls)) {
                owner[s] = i;
                ops[i].slot = uint8_t(s);
                return true;
            }
        for (int s = 0; s < nslots; ++s) {
            if (seen[s] || !m.slots[s].accepts(ops[i].info().cls)) continue;
            seen[s] = true;
            int cur = owner[s];
            if (cur >= 0 && pinned[cur] >= 0) continue;
            if (cur < 0 || self(self, cur, seen)) {
                owner[s] = i;
                ops[i].slot = uint8_t(s);
                return true;
            }
        }
        return false;
    };
    for (size_t i = 0; i < ops.size(); ++i) {
        if (pinned[i] >= 0) continue;
        std::array<bool, kMaxSlots> seen{};
        if (!place(place, int(i), seen)) return false;
    }
    return true;
}

BundleUsage bundle_usage(std::span<const Instr> ops) {
    BundleUsage u;
    for (const Instr& in : ops) {
        PortUse p = port_use(in.info());
        for (int f = 0; f < kNumRegFiles; ++f) {
            u.reads[f] += p.reads[f];
            u.writes[f] += p.writes[f];
        }
        if (in.info().kind != Kind::Nop) ++u.ops;
    }
    return u;
}

} // namespace nesshi::isa
