// What compiled runs (iss/compiled.hpp) are made of: the generated code of a straight run calls
// op<O, Direct>(...) with constant operands for each operation and one of end/jump/stop for
// each bundle's end, and nothing else of the engine, so that the engine can change behind these.
//
// A compiled run is entered at the bundle core.pc and leaves the core exactly as the threaded
// chain (chain.hpp) would: op<> is exec<> (handlers.hpp) with its operands known, its semantics
// isa::kOps[O].eval; end<> is then<kEnd + flags>, jump<> then<kJump + flags>, stop() kExit.
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
#include <cstring>

namespace nesshi::iss::detail {

// run_plain's hook: the compiled runs from core.pc until one stops.
inline void run_compiled(Core& c) {
    while (c.compiled[c.pc](c)) {}
}

// Source F of row O from register `reg`, or 0 when the row does not read it (as src<>).
template <size_t O, isa::Field F> [[gnu::always_inline]] inline uint32_t csrc(const Core& c, uint16_t reg) {
    if constexpr (!uses_field(isa::kOps[O], F)) return 0;
    else return c.r[reg];
}

template <bool Direct>
[[gnu::always_inline]] inline void cput(Core& c, uint16_t dst, uint32_t lat, uint32_t index, uint32_t v) {
    if constexpr (Direct) c.r[dst] = v;
    else c.push(dst, lat, index, v);
}

// Misses through the checked access with the op's record (a fault names it).
template <size_t O, bool Direct> [[gnu::noinline]] void cload_miss(Core& c, uint32_t index, uint32_t addr) {
    const DecodedOp& d = c.ops[index];
    const uint64_t v = c.load_checked(d, addr, isa::kOps[O].mem_bytes);
    if (v != Core::kLoadFailed) put<Direct>(c, d, extend<O>(uint32_t(v)));
}
template <size_t O> [[gnu::noinline]] void cstore_miss(Core& c, uint32_t index, uint32_t addr, uint32_t v) {
    c.store_checked(c.ops[index], addr, isa::kOps[O].mem_bytes, v);
}

// Row O with its operands given: exec<O, Direct, kReturn> for a DecodedOp with these fields.
template <size_t O, bool Direct>
[[gnu::always_inline]] inline void op(Core& c, uint16_t dst, uint16_t ra, uint16_t rb, uint16_t rc, uint32_t imm,
                                      uint32_t lat, uint32_t index, uint32_t bundle) {
    using isa::Field;
    using isa::Kind;
    constexpr const isa::OpInfo& info = isa::kOps[O];
    constexpr isa::Eval eval = info.eval;
    const uint32_t a = csrc<O, Field::Rs1>(c, ra);
    const uint32_t b = csrc<O, Field::Rs2>(c, rb);
    const uint32_t cc = csrc<O, Field::Rs3>(c, rc);
    if constexpr (info.kind == Kind::Compute) {
        cput<Direct>(c, dst, lat, index, eval(a, b, cc, imm));
    } else if constexpr (info.kind == Kind::Load) {
        const uint32_t addr = eval(a, b, cc, imm);
        if (!c.mem->tlb_hit<info.mem_bytes>(addr)) [[unlikely]]
            return cload_miss<O, Direct>(c, index, addr);
        uint32_t v = 0;
        std::memcpy(&v, c.mem->tlb_data(addr), info.mem_bytes);
        cput<Direct>(c, dst, lat, index, extend<O>(v));
    } else if constexpr (info.kind == Kind::Store) {
        const uint32_t addr = eval(a, b, cc, imm);
        if (!c.mem->tlb_hit<info.mem_bytes>(addr)) [[unlikely]]
            return cstore_miss<O>(c, index, addr, b);
        std::memcpy(c.mem->tlb_data(addr), &b, info.mem_bytes);
    } else if constexpr (info.kind == Kind::Branch) {
        if (eval(a, b, cc, imm)) {
            c.next_pc = imm;
            c.event |= kTaken;
        }
    } else if constexpr (info.kind == Kind::Jump) {
        c.next_pc = imm;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpLink) {
        cput<Direct>(c, dst, lat, index, bundle + 1);
        c.next_pc = imm;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpReg) {
        c.next_pc = a;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::Halt) {
        c.event |= kHalt;
    } else if constexpr (info.kind == Kind::Recv || info.kind == Kind::Send) {
        exec<O, Direct, kReturn>(c, c.ops[index]); // its gate has passed (loop()'s, or end<>'s or jump<>'s fast one)
    } else {
        static_assert(info.kind == Kind::Nop);
    }
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
