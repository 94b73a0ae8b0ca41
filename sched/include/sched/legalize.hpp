// Hand-scheduled code on a slower machine: the loops and glue of our kernels are bundled by hand
// for the ideal presets, where most results land a cycle after issue. On a machine with longer
// latencies (os-real, seq-real, a user's TOML) the same bundles would read values still in
// flight, which the exposed pipeline forbids. legalize() inserts nop bundles until the
// assembler's hazard check accepts the code: before each bundle that reads a value too early
// (as many as the value still needs), one before a bundle whose results would land in one
// cycle beyond the write ports or twice on one register, and before a bundle whose write would
// land before an earlier write to its register as many as put it one cycle after that one; a
// bundle that reads or writes beyond the ports (a machine with fewer of them) loses an op to a
// bundle of its own just before it, when that keeps the meaning. A nop only delays, so the meaning stays
// the one the code has on the machine it was written for: a read in the overwriting producer's
// bundle or earlier sees the old value on every machine, any later read must see the new one.
//
//   auto check = [&](const std::string& t) -> std::optional<std::string> { ... diagnostics or nullopt };
//   sched::Legalized l = sched::legalize(text, "kernels/os/dda.pk", check);
//   l.text ... l.nops (how many were inserted), l.lines (before which lines of the original)
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace nesshi::sched {

struct Legalized {
    std::string text;
    int nops = 0;                    // nop bundles inserted
    int splits = 0;                  // ops moved out of a bundle beyond the read or write ports
    std::vector<std::string> where;  // "LINE: N nops (REASON)" against the original text's lines
};

// `check` assembles a candidate text and returns its rendered diagnostics, or nullopt when it is
// accepted. Errors located in `filename` (FILE:LINE:COL: error: ...) about a value read in flight,
// write ports, a double write or a write out of order are fixed; a `#pack begin` ... `#pack end` block is not entered
// (its nops go before its `#pack begin`: the block's own ops are scheduled by the tool). Throws
// base::Error with the diagnostics when another error remains or no progress is made.
Legalized legalize(const std::string& text, const std::string& filename,
                   const std::function<std::optional<std::string>(const std::string&)>& check);

} // namespace nesshi::sched
