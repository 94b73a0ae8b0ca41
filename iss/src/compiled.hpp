// What compiled runs (iss/compiled.hpp) are made of: the generated code of a straight run calls
// op<O, Direct>(...) with constant operands for each operation and one of end/jump/stop for
// each bundle's end, and nothing else of the engine, so that the engine can change behind these.
//
// A compiled run is entered at the bundle core.pc and leaves the core exactly as the threaded
// chain (chain.hpp) would: op<> is the handlers' semantics<> (handlers.hpp) with its operands
// known, so isa::kOps[O].eval; end<> is then<kEnd + flags>, jump<> then<kJump + flags>, stop() kExit.
// The run entry/exit contract at the top of chain.hpp holds for them as for the chain: a bundle
// ends through chain.hpp's finish<> (execution counts by pass), and a run goes into a FIFO bundle
// only when gate_at_issue passes.
// It returns true when control goes on to another run (core.pc is the next bundle, not issued
// yet: run_compiled enters that run) and false when it stops in bundle core.pc with its ops
// executed, which EngineLoop::run_plain and loop() then finish as after a chain.
#pragma once

#include "chain.hpp"
#include "core.hpp"
#include "handlers.hpp"

#include "isa/ops.hpp"

#include <cstdint>

namespace nesshi::iss::detail {

// run_plain's hook: the compiled runs from core.pc until one stops.
inline void run_compiled(Core& c) {
    while (c.compiled[c.pc](c)) {}
}

// An op's fields as constants of the generated code (handlers.hpp's FromRecord for records).
struct Constants {
    uint16_t dst_, a_, b_, c_;
    uint32_t imm_, latency_, index_, bundle_;
    uint16_t dst() const { return dst_; }
    uint16_t reg(isa::Field f) const { return f == isa::Field::Rs1 ? a_ : f == isa::Field::Rs2 ? b_ : c_; }
    uint32_t imm() const { return imm_; }
    uint32_t latency() const { return latency_; }
    uint32_t index() const { return index_; }
    uint32_t bundle() const { return bundle_; }
    const DecodedOp& record(const Core& c) const { return c.ops[index_]; } // misses, FIFO channels
};

// Row O with its operands given: the handlers' semantics, ending as kReturn.
template <size_t O, bool Direct>
[[gnu::always_inline]] inline void op(Core& c, uint16_t dst, uint16_t ra, uint16_t rb, uint16_t rc, uint32_t imm,
                                      uint32_t lat, uint32_t index, uint32_t bundle) {
    semantics<O, Direct, kReturn>(c, Constants{dst, ra, rb, rc, imm, lat, index, bundle});
}

// The ring writes landing now, once a bundle of a run has ended (land_then without its tail).
[[gnu::noinline]] inline void cland_ring(Core& c, uint32_t prev_bundle) { land_ring(c, prev_bundle); }
[[gnu::always_inline]] inline void cland(Core& c, uint32_t prev_bundle) {
    if (c.ring[c.cycle & c.mask].n) cland_ring(c, prev_bundle);
}

// The last bundle of a run that does not jump (kExit): the chain stops in it.
[[gnu::always_inline]] inline bool stop(Core& c, uint32_t bundle) {
    c.pc = bundle;
    return false;
}

// The gate of FIFO bundle `to` before a compiled run goes into it (gate_at_issue, out of line).
[[gnu::noinline]] inline bool cgate(Core& c, uint32_t to) { return gate_at_issue(c, to); }

// The end of bundle `bundle` inside a run (then<kEnd + flags>): false when the chain stops in it
// (Gate: the next bundle is a FIFO bundle, entered only when its fast gate passes).
template <bool Commit, bool Events, bool Gate> [[gnu::always_inline]] inline bool end(Core& c, uint32_t bundle) {
    if constexpr (Events)
        if (c.event) [[unlikely]]
            return stop(c, bundle);
    if (c.left == 0) [[unlikely]]
        return stop(c, bundle);
    if constexpr (Gate)
        if (!cgate(c, bundle + 1)) [[unlikely]]
            return stop(c, bundle);
    finish<Commit, false>(c, bundle, bundle + 1);
    if (c.pending) [[unlikely]]
        cland(c, bundle);
    return true;
}

// The end of control bundle `bundle` when the chain goes on across it (then<kJump + flags>):
// the bundle it goes to, or kStopped (the chain stops in it).
inline constexpr uint32_t kStopped = ~uint32_t{0};
template <bool Commit> [[gnu::always_inline]] inline uint32_t jump(Core& c, uint32_t bundle) {
    const uint32_t ev = c.event;
    if ((ev & ~uint32_t{kTaken}) || c.left == 0) [[unlikely]] {
        c.pc = bundle;
        return kStopped;
    }
    const uint32_t to = ev ? c.next_pc : bundle + 1;
    if (to >= c.nb || (c.bundles[to].slow && !cgate(c, to))) [[unlikely]] {
        c.pc = bundle;
        return kStopped;
    }
    finish<Commit, true>(c, bundle, to);
    if (c.pending) [[unlikely]]
        cland(c, bundle);
    return to;
}

// For the generator: what the engine's form of the program says of an op and a bundle.
inline bool op_direct(const DecodedOp& d) { return d.fn == kDirectHandlers[d.instr.opcode]; }

} // namespace nesshi::iss::detail
