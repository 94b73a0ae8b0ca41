// Per-operation handlers, generated from the ISA table at compile time.
//
// handler_table() instantiates exec<O> for every row O of isa::kOps with std::index_sequence;
// each instantiation inlines its row's `eval` and does what the row's Kind says. There is no
// hand-written per-opcode switch: adding a row to kOps adds its handler.
#pragma once

#include "chain.hpp"
#include "core.hpp"

#include "isa/ops.hpp"

#include <array>
#include <cstring>
#include <type_traits>
#include <utility>

namespace nesshi::iss::detail {

constexpr bool uses_field(const isa::OpInfo& info, isa::Field f) {
    for (int i = 0; i < info.num_operands; ++i) {
        const isa::Operand& o = info.operands[i];
        if (o.is_dest) continue;
        if (o.field == f && (o.kind == isa::OperandKind::IntReg || o.kind == isa::OperandKind::FloatReg))
            return true;
        if (o.kind == isa::OperandKind::Mem && f == isa::Field::Rs1) return true;
    }
    return false;
}

// The fields of an operation that its semantics read: from its record (R: DecodedOp for the
// dispatch loop's handlers, ThreadedOp for threaded ones, whose cold fields are in c.ops), or
// given as constants (compiled runs, compiled.hpp, where record() is only asked on rare paths).
template <class R> struct FromRecord {
    const R& d;
    uint16_t dst() const { return d.dst; }
    uint16_t reg(isa::Field f) const { return f == isa::Field::Rs1 ? d.a : f == isa::Field::Rs2 ? d.b : d.c; }
    uint32_t imm() const { return d.imm; }
    uint32_t latency() const { return d.latency; }
    uint32_t index() const { return d.index; }
    uint32_t bundle() const { return d.bundle; }
    const DecodedOp& record(const Core& c) const {
        if constexpr (std::is_same_v<R, DecodedOp>) return d;
        else return c.ops[d.index];
    }
    const R& op() const { return d; } // what a threaded tail goes on from
};

// Source F of row O, or 0 when the row does not read it. The choice is made at compile time:
// asked of a run-time reference to the row, GCC kept the scan of its operand table in every
// handler (a third of the engine's host instructions).
template <size_t O, isa::Field F, class Fields>
[[gnu::always_inline]] inline uint32_t src(const Core& c, const Fields& f) {
    if constexpr (!uses_field(isa::kOps[O], F)) return 0;
    else return c.r[f.reg(F)];
}

// Direct: the result has latency 1 and no later operation of the bundle reads its register, so
// it can be written in place (the load-time decoder proves this per operation). Otherwise the
// write is queued (issued in cycle `now`) and lands after every operation of the bundle has read
// its sources.
template <bool Direct, class Fields>
[[gnu::always_inline]] inline void put(Core& c, const Fields& f, uint32_t v, uint64_t now) {
    if constexpr (Direct) c.r[f.dst()] = v;
    else c.push_at(now, f.dst(), f.latency(), f.index(), v);
}

// A loaded value of row O, extended to 32 bits.
template <size_t O> constexpr uint32_t extend(uint32_t v) {
    constexpr const isa::OpInfo& info = isa::kOps[O];
    if constexpr (info.mem_signed && info.mem_bytes == 1) return uint32_t(int32_t(int8_t(v)));
    else if constexpr (info.mem_signed && info.mem_bytes == 2) return uint32_t(int32_t(int16_t(v)));
    else return v;
}

// A load or store the TLB does not serve: the checked access (range, alignment, stalls). Out of
// line and reached by a tail call, so that the hit path of the handler needs no stack frame;
// it ends as the handler would (its Tail T and the chain's state, chain.hpp).
template <size_t O, bool Direct, int T, class R>
[[gnu::noinline]] void load_miss(Core& c, const R& d, uint64_t cycle, uint64_t left, uint32_t addr) {
    const FromRecord<R> f{d};
    c.cycle = cycle; // a host's cache model may ask its processor's cycle()
    const uint64_t v = c.load_checked(f.record(c), addr, isa::kOps[O].mem_bytes);
    if (v != Core::kLoadFailed) put<Direct>(c, f, extend<O>(uint32_t(v)), cycle);
    return then<T>(c, d, cycle, left);
}
template <size_t O, int T, class R>
[[gnu::noinline]] void store_miss(Core& c, const R& d, uint64_t cycle, uint64_t left, uint32_t addr, uint32_t v) {
    c.cycle = cycle;
    c.store_checked(FromRecord<R>{d}.record(c), addr, isa::kOps[O].mem_bytes, v);
    return then<T>(c, d, cycle, left);
}
// What a miss and the tail go on from: the record (kReturn), or the threaded op.
template <int T, class Fields> [[gnu::always_inline]] inline decltype(auto) tail_record(const Core& c, const Fields& f) {
    if constexpr (T == kReturn) return f.record(c);
    else return f.op();
}

// Row O's semantics on an op's fields (FromRecord, or a compiled run's constants), then its Tail
// T: kReturn for the dispatch loop and compiled runs, the others for threaded runs. `cycle` is
// the op's issue cycle, which a run keeps out of c.cycle (chain.hpp, compiled.hpp Counts): it is
// written there before anything a host provides (a channel, a cache model) may ask for it;
// `left`, the chain's budget, only goes on to its tail.
template <size_t O, bool Direct, int T, class Fields>
[[gnu::always_inline]] inline void semantics(Core& c, const Fields& f, uint64_t cycle, uint64_t left) {
    using isa::Field;
    using isa::Kind;
    constexpr const isa::OpInfo& info = isa::kOps[O];
    constexpr isa::Eval eval = info.eval;
    const uint32_t a = src<O, Field::Rs1>(c, f);
    const uint32_t b = src<O, Field::Rs2>(c, f);
    const uint32_t cc = src<O, Field::Rs3>(c, f);
    auto put = [&](uint32_t v) { detail::put<Direct>(c, f, v, cycle); };
    if constexpr (info.kind == Kind::Compute) {
        put(eval(a, b, cc, f.imm()));
    } else if constexpr (info.kind == Kind::Load) {
        const uint32_t addr = eval(a, b, cc, f.imm());
        if (!c.mem->tlb_hit<info.mem_bytes>(addr)) [[unlikely]]
            return load_miss<O, Direct, T>(c, tail_record<T>(c, f), cycle, left, addr);
        uint32_t v = 0;
        std::memcpy(&v, c.mem->tlb_data(addr), info.mem_bytes); // little-endian host assumed, as in PagedMemory
        put(extend<O>(v));
    } else if constexpr (info.kind == Kind::Store) {
        const uint32_t addr = eval(a, b, cc, f.imm());
        if (!c.mem->tlb_hit<info.mem_bytes>(addr)) [[unlikely]]
            return store_miss<O, T>(c, tail_record<T>(c, f), cycle, left, addr, b);
        std::memcpy(c.mem->tlb_data(addr), &b, info.mem_bytes); // little-endian host assumed, as in PagedMemory
    } else if constexpr (info.kind == Kind::Branch) {
        if (eval(a, b, cc, f.imm())) {
            c.next_pc = f.imm();
            c.event |= kTaken;
        }
    } else if constexpr (info.kind == Kind::Jump) {
        c.next_pc = f.imm();
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpLink) {
        put(f.bundle() + 1); // not c.pc: the fast engine updates it only at the end of a run
        c.next_pc = f.imm();
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpReg) {
        c.next_pc = a;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::Recv) {
        // The FIFO gate (the engine's, or the chain's fast one) has checked that the channel
        // exists and holds a word.
        // A bundle's words from one channel come in one call, at its first receive.
        c.cycle = cycle; // for a host's channel
        const DecodedOp& r = f.record(c);
        if (!r.batch) put(c.channels[r.chan]->pop());
        else {
            if (r.need == 1) c.channels[r.chan]->pop_n(c.fifo_in.data(), r.batch);
            put(c.fifo_in[r.need - 1u]);
        }
        ++*c.words_received;
    } else if constexpr (info.kind == Kind::Send) {
        // A bundle's words into one channel go in one call, at its last send.
        c.cycle = cycle;
        const DecodedOp& r = f.record(c);
        if (!r.batch) c.channels[r.chan]->push(a, cycle);
        else {
            c.fifo_out[r.need - 1u] = a;
            if (r.need == r.batch) c.channels[r.chan]->push_n(c.fifo_out.data(), r.batch, cycle);
        }
        ++*c.words_sent;
    } else if constexpr (info.kind == Kind::Halt) {
        c.event |= kHalt;
    } else {
        static_assert(info.kind == Kind::Nop);
    }
    return then<T>(c, tail_record<T>(c, f), cycle, left);
}
// The handler of row O: for the dispatch loop (kReturn), or a threaded one.
template <size_t O, bool Direct> void exec(Core& c, const DecodedOp& d) {
    return semantics<O, Direct, kReturn>(c, FromRecord<DecodedOp>{d}, c.cycle, c.left);
}
template <size_t O, bool Direct, int T> void texec(Core& c, const ThreadedOp& d, uint64_t cycle, uint64_t left) {
    return semantics<O, Direct, T>(c, FromRecord<ThreadedOp>{d}, cycle, left);
}

template <bool Direct, size_t... I> constexpr std::array<Handler, sizeof...(I)> make_table(std::index_sequence<I...>) {
    return {&exec<I, Direct>...};
}
template <bool Direct, int T, size_t... I>
constexpr std::array<ThreadedHandler, sizeof...(I)> make_ttable(std::index_sequence<I...>) {
    return {&texec<I, Direct, T>...};
}
template <bool Direct, int T>
inline constexpr std::array<ThreadedHandler, isa::kNumOps> kTable =
    make_ttable<Direct, T>(std::make_index_sequence<isa::kNumOps>{});

inline constexpr std::array<Handler, isa::kNumOps> kHandlers = make_table<false>(std::make_index_sequence<isa::kNumOps>{});
inline constexpr std::array<Handler, isa::kNumOps> kDirectHandlers = make_table<true>(std::make_index_sequence<isa::kNumOps>{});
// Whether the decoder let op d write its result in place (Program, the compiled-run generator).
inline bool op_direct(const DecodedOp& d) { return d.fn == kDirectHandlers[d.instr.opcode]; }

// The threaded handlers of Tail T, plain or direct. Instantiated only in threaded_tails_*.cpp, three
// tails per file, so that a build spreads the 24 tables over its cores (in one file they took
// 153 s under ASan, the sanitizer build's longest compile).
template <int T> const std::array<ThreadedHandler, isa::kNumOps>& tail_table(bool direct) {
    return direct ? kTable<true, T> : kTable<false, T>;
}
#define NESSHI_TAIL_TABLE(T) extern template const std::array<ThreadedHandler, isa::kNumOps>& tail_table<T>(bool);
NESSHI_TAIL_TABLE(1) NESSHI_TAIL_TABLE(2) NESSHI_TAIL_TABLE(3) NESSHI_TAIL_TABLE(4) NESSHI_TAIL_TABLE(5) NESSHI_TAIL_TABLE(6)
NESSHI_TAIL_TABLE(7) NESSHI_TAIL_TABLE(8) NESSHI_TAIL_TABLE(9) NESSHI_TAIL_TABLE(10) NESSHI_TAIL_TABLE(11) NESSHI_TAIL_TABLE(12)
#undef NESSHI_TAIL_TABLE

// The threaded handler of `opcode` with Tail `tail` (not kReturn).
inline ThreadedHandler threaded_handler(uint32_t opcode, bool direct, int tail) {
    static_assert(kNumTails == 13);
    using Table = const std::array<ThreadedHandler, isa::kNumOps>& (*)(bool);
    static constexpr std::array<Table, kNumTails - 1> kTails = {&tail_table<1>, &tail_table<2>,  &tail_table<3>,  &tail_table<4>,
                                                               &tail_table<5>, &tail_table<6>,  &tail_table<7>,  &tail_table<8>,
                                                               &tail_table<9>, &tail_table<10>, &tail_table<11>, &tail_table<12>};
    return kTails[static_cast<std::size_t>(tail - 1)](direct)[opcode];
}

} // namespace nesshi::iss::detail
