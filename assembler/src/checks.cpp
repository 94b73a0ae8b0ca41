// Bundle checks (see checks.hpp).
#include "checks.hpp"

#include "isa/bundle_check.hpp"

#include <fmt/format.h>

namespace nesshi::assembler {

namespace {
bool slot_rule(isa::Rule r) {
    return r == isa::Rule::SlotRange || r == isa::Rule::SlotClass || r == isa::Rule::SlotTwice;
}

std::string slots_accepting(const isa::Machine& m, isa::OpClass c) {
    std::string s;
    for (const auto& slot : m.slots)
        if (slot.accepts(c)) s += (s.empty() ? "" : ", ") + slot.name;
    return s.empty() ? "none" : s;
}
} // namespace

bool check_bundle_rules(BundleRec& b, const isa::Machine& m, Diagnostics& diags) {
    std::vector<isa::Instr> ops;
    std::vector<int> pins;
    for (const auto& o : b.ops) {
        ops.push_back(o.instr);
        pins.push_back(o.pin);
    }
    bool ok = true;
    // Each op takes the first free slot that accepts it, in source order; ops move only when
    // that gets stuck (isa::assign_slots).
    bool assign_failed = !isa::assign_slots(m, ops, pins);
    if (assign_failed) {
        // Find the first unpinned op that cannot be placed given the ones before it.
        for (size_t k = 0; k < ops.size(); ++k) {
            if (pins[k] >= 0) continue;
            std::vector<isa::Instr> pre(ops.begin(), ops.begin() + long(k) + 1);
            std::vector<int> pp(pins.begin(), pins.begin() + long(k) + 1);
            // Pinned ops after k still hold their slots.
            for (size_t j = k + 1; j < ops.size(); ++j)
                if (pins[j] >= 0) {
                    pre.push_back(ops[j]);
                    pp.push_back(pins[j]);
                }
            if (isa::assign_slots(m, pre, pp)) continue;
            const isa::OpInfo& info = ops[k].info();
            bool pinned_clash = false;
            for (size_t j = 0; j < ops.size(); ++j)
                for (size_t i = 0; i < j; ++i)
                    if (pins[i] >= 0 && pins[i] == pins[j]) pinned_clash = true;
            if (pinned_clash) break;
            diags.error(b.ops[k].loc,
                        fmt::format("no free issue slot for '{}' (class {}; {} slots accepting it: {})",
                                    info.mnemonic, isa::kOpClassNames[size_t(info.cls)], m.name,
                                    slots_accepting(m, info.cls)));
            ok = false;
            break;
        }
        // Give every op some slot so the register rules can still run.
        for (size_t i = 0; i < ops.size(); ++i) ops[i].slot = uint8_t(pins[i] >= 0 ? pins[i] : 0);
    }
    for (const isa::Violation& v : isa::check_bundle(m, ops)) {
        if (slot_rule(v.rule)) {
            bool involves_unpinned = pins[size_t(v.op)] < 0 || (v.other >= 0 && pins[size_t(v.other)] < 0);
            if (assign_failed && involves_unpinned) continue; // consequence of the failed assignment
        }
        Diagnostic& d = diags.error(b.ops[size_t(v.op)].loc, v.message);
        if (v.other >= 0 && !v.note.empty()) Diagnostics::note(d, b.ops[size_t(v.other)].loc, v.note);
        ok = false;
    }
    for (size_t i = 0; i < ops.size(); ++i) b.ops[i].instr.slot = ops[i].slot;
    return ok;
}

} // namespace nesshi::assembler
