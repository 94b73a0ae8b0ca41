// Per-operation handlers, generated from the ISA table at compile time.
//
// handler_table() instantiates exec<O> for every row O of isa::kOps with std::index_sequence;
// each instantiation inlines its row's `eval` and does what the row's Kind says. There is no
// hand-written per-opcode switch: adding a row to kOps adds its handler.
#pragma once

#include "core.hpp"

#include "isa/ops.hpp"

#include <array>
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

template <isa::Field F> inline uint32_t src(const Core& c, const DecodedOp& d, const isa::OpInfo& info) {
    if (!uses_field(info, F)) return 0;
    if constexpr (F == isa::Field::Rs1) return c.r[d.a];
    else if constexpr (F == isa::Field::Rs2) return c.r[d.b];
    else return c.r[d.c];
}

// Direct: the result has latency 1 and no later operation of the bundle reads its register, so
// it can be written in place (the load-time decoder proves this per operation). Otherwise the
// write is queued and lands after every operation of the bundle has read its sources.
template <size_t O, bool Direct> void exec(Core& c, const DecodedOp& d) {
    using isa::Field;
    using isa::Kind;
    constexpr const isa::OpInfo& info = isa::kOps[O];
    constexpr isa::Eval eval = info.eval;
    const uint32_t a = src<Field::Rs1>(c, d, info);
    const uint32_t b = src<Field::Rs2>(c, d, info);
    const uint32_t cc = src<Field::Rs3>(c, d, info);
    auto put = [&](uint32_t v) {
        if constexpr (Direct) c.r[d.dst] = v;
        else c.push(d, v);
    };
    if constexpr (info.kind == Kind::Compute) {
        put(eval(a, b, cc, d.imm));
    } else if constexpr (info.kind == Kind::Load) {
        uint32_t v;
        if (!c.load<info.mem_bytes>(d, eval(a, b, cc, d.imm), v)) return;
        if constexpr (info.mem_signed && info.mem_bytes == 1) v = uint32_t(int32_t(int8_t(v)));
        if constexpr (info.mem_signed && info.mem_bytes == 2) v = uint32_t(int32_t(int16_t(v)));
        put(v);
    } else if constexpr (info.kind == Kind::Store) {
        c.store<info.mem_bytes>(d, eval(a, b, cc, d.imm), b);
    } else if constexpr (info.kind == Kind::Branch) {
        if (eval(a, b, cc, d.imm)) {
            c.next_pc = d.imm;
            c.event |= kTaken;
        }
    } else if constexpr (info.kind == Kind::Jump) {
        c.next_pc = d.imm;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpLink) {
        put(c.pc + 1);
        c.next_pc = d.imm;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::JumpReg) {
        c.next_pc = a;
        c.event |= kTaken;
    } else if constexpr (info.kind == Kind::Recv) {
        // The engine's FIFO gate has checked that the channel exists and holds a word.
        put(c.channels[d.chan]->pop());
        ++*c.words_received;
    } else if constexpr (info.kind == Kind::Send) {
        c.channels[d.chan]->push(a, c.cycle);
        ++*c.words_sent;
    } else if constexpr (info.kind == Kind::Halt) {
        c.event |= kHalt;
    } else {
        static_assert(info.kind == Kind::Nop);
    }
}

template <bool Direct, size_t... I>
constexpr std::array<Handler, sizeof...(I)> make_table(std::index_sequence<I...>) {
    return {&exec<I, Direct>...};
}

inline constexpr std::array<Handler, isa::kNumOps> kHandlers =
    make_table<false>(std::make_index_sequence<isa::kNumOps>{});
inline constexpr std::array<Handler, isa::kNumOps> kDirectHandlers =
    make_table<true>(std::make_index_sequence<isa::kNumOps>{});

} // namespace nesshi::iss::detail
