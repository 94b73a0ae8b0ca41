// Lock-step comparison of the two engines (see lockstep.hpp).
#include "iss/lockstep.hpp"

#include <fmt/core.h>

namespace nesshi::iss {

namespace {
std::optional<std::string> compare(const Processor& a, const Processor& b) {
    if (a.status() != b.status())
        return fmt::format("status: fast {}, checked {}", status_name(a.status()), status_name(b.status()));
    // After the same fault the state must agree too: a faulting bundle issues all but the faulting
    // access in both engines.
    if (a.status() == Status::Faulted &&
        (a.fault()->kind != b.fault()->kind || a.fault()->cycle != b.fault()->cycle || a.fault()->pc != b.fault()->pc))
        return fmt::format("faults: fast {} at cycle {}, checked {} at cycle {}", fault_rule(a.fault()->kind),
                           a.fault()->cycle, fault_rule(b.fault()->kind), b.fault()->cycle);
    if (a.pc() != b.pc()) return fmt::format("pc: fast {}, checked {}", a.pc(), b.pc());
    if (a.cycle() != b.cycle()) return fmt::format("cycle: fast {}, checked {}", a.cycle(), b.cycle());
    for (uint16_t r = 0; r < kNumRegs; ++r)
        if (a.reg(r) != b.reg(r))
            return fmt::format("{}: fast 0x{:08x}, checked 0x{:08x}", reg_name(r), a.reg(r), b.reg(r));
    auto ia = a.inflight(), ib = b.inflight();
    if (ia.size() != ib.size()) return fmt::format("in-flight writes: fast {}, checked {}", ia.size(), ib.size());
    for (size_t i = 0; i < ia.size(); ++i)
        if (ia[i].reg != ib[i].reg || ia[i].value != ib[i].value || ia[i].lands != ib[i].lands)
            return fmt::format("in-flight write {}: fast {} lands {}, checked {} lands {}", i, reg_name(ia[i].reg),
                               ia[i].lands, reg_name(ib[i].reg), ib[i].lands);
    return std::nullopt;
}
} // namespace

LockstepResult run_lockstep(Processor& fast, Processor& checked, uint64_t max_cycles) {
    LockstepResult res;
    uint64_t limit = max_cycles;
    while (true) {
        uint64_t before_pc = fast.pc(), before_cycle = fast.cycle();
        // The limit holds inside a step too: a bundle waiting on a FIFO stops at it.
        auto left = [limit](const Processor& p) { return limit > p.cycle() ? limit - p.cycle() : 0; };
        Status sf = fast.step(1, left(fast));
        Status sc = checked.step(1, left(checked));
        ++res.bundles;
        if (sc == Status::Faulted && sf != Status::Faulted) { // a dynamic rule the fast engine trusts
            res.status = sc;
            res.fault = checked.fault();
            return res;
        }
        auto diff = compare(fast, checked);
        if (!diff && (sf == Status::Halted || sf == Status::Faulted)) {
            if (fast.memory().hash() != checked.memory().hash()) diff = "memory contents differ";
            else if (fast.counters().exec != checked.counters().exec) diff = "bundle execution counts differ";
            else
                for (int f = 0; f < isa::kNumRegFiles && !diff; ++f)
                    if (fast.write_histogram(f) != checked.write_histogram(f)) diff = "write-port histograms differ";
        }
        if (diff) {
            res.status = Status::Faulted;
            res.fault = Fault{FaultKind::Divergence, before_cycle, uint32_t(before_pc),
                              fmt::format("fast and checked engines diverge after this bundle: {}", *diff), {}};
            return res;
        }
        res.status = sf;
        if (sf != Status::Running) {
            if (sf == Status::Faulted) res.fault = fast.fault();
            return res;
        }
        if (fast.cycle() >= limit) return res;
    }
}

} // namespace nesshi::iss
