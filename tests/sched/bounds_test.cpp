// sched/bounds.hpp: ResMII and the region RecMII on small hand-written loops whose bounds are
// worked out by hand in the comments, on os, ic and seq.
#include "sched/bounds.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <string>
#include <vector>

using namespace nesshi;

namespace {

// The operations of `body` (bundles after the label `loop`; a `halt` after it ends the code),
// nops left out, with their bundles.
std::vector<sched::BodyOp> body_ops(const isa::Machine& m, const std::string& body) {
    const std::string text = "        .text\nloop:\n" + body + "        halt\n";
    const assembler::AsmResult r = assembler::assemble_string(text, "t.s", m, {});
    INFO(r.diagnostics);
    REQUIRE(r.ok);
    REQUIRE(r.warnings == 0);
    std::vector<sched::BodyOp> out;
    const auto bundles = isa::decode_bundles(r.object);
    for (std::uint32_t b = 0; b + 1 < bundles.size(); ++b)
        for (const isa::Instr& in : bundles[b])
            if (in.info().kind != isa::Kind::Nop) out.push_back({in, b});
    return out;
}

std::vector<isa::Instr> instrs(const std::vector<sched::BodyOp>& ops) {
    std::vector<isa::Instr> out;
    for (const sched::BodyOp& o : ops) out.push_back(o.instr);
    return out;
}

sched::ResBound res(const isa::Machine& m, const std::string& body, std::span<const sched::ExtraOps> extra = {}) {
    return sched::res_mii(m, instrs(body_ops(m, body)), extra);
}

} // namespace

TEST_CASE("ResMII on os: the integer slots bind a saxpy body", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // Only iu0 and iu1 take loads, stores, addi and bne: 5 ops on 2 slots. The FPUs have 2 ops for
    // 2 slots, all 4 slots 7 ops, iu0 alone (the only branch slot) 1 op.
    const char* body = R"(
        { flw f1, 0(r1) ; flw f2, 0x400(r1) }
        { fmul f3, f0, f1 }
        { fadd f4, f3, f2 }
        { fsw f4, 0x400(r1) ; addi r1, r1, 4 }
        bne r1, r9, loop
)";
    const sched::ResBound r = res(m, body);
    CHECK(r.cycles == 2.5);
    CHECK(r.ii() == 3);
    CHECK(r.binds == "slots {iu0,iu1}: 5 ops / 2 = 2.50");
}

TEST_CASE("ResMII: extra loop-control ops take slots of their class", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // 4 IU ops; with the counter's addi and the bnez the two IU slots carry 6 ops.
    const char* body = R"(
        { flw f1, 0(r1) ; flw f2, 0x400(r1) }
        { fmul f3, f0, f1 }
        { fadd f4, f3, f2 }
        { fsw f4, 0x400(r1) ; addi r1, r1, 4 }
)";
    CHECK(res(m, body).cycles == 2);
    const sched::ResBound r = res(m, body, sched::kLoopControl);
    CHECK(r.cycles == 3);
    CHECK(r.binds == "slots {iu0,iu1}: 6 ops / 2 = 3");
    // A branch-only extra binds iu0, the only slot that accepts branches: 3 / 1.
    const sched::ExtraOps branches[] = {{isa::OpClass::Branch, 3}};
    CHECK(sched::res_mii(m, {}, branches).binds == "slots {iu0}: 3 ops / 1 = 3");
}

TEST_CASE("ResMII on os: the FPRF write ports bind four loads and four adds", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // Slots: 4 loads on 2 IUs, 4 fadds on 2 FPUs, 8 ops on 4 slots: 2 each. But all 8 write the
    // FPRF, which has 2 write ports: 4.
    const char* body = R"(
        { flw f1, 0(r1) ; flw f2, 4(r1) }
        { fadd f10, f20, f21 ; fadd f11, f22, f23 }
        { flw f3, 8(r1) ; flw f4, 12(r1) }
        { fadd f12, f24, f25 ; fadd f13, f26, f27 }
)";
    const sched::ResBound r = res(m, body);
    CHECK(r.cycles == 4);
    CHECK(r.ii() == 4);
    CHECK(r.binds == "FPRF write ports 8/2 = 4");
}

TEST_CASE("ResMII on os: the FPRF read ports bind two adds and two float stores", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // Every slot takes 1 op; the FPRF is read 2 x 2 (fadd) + 2 x 1 (fsw data) = 6 times through 5
    // read ports (one bundle could not hold them all; the bound is per iteration).
    const char* body = R"(
        { fsw f1, 0(r1) ; fsw f2, 4(r1) ; fadd f10, f20, f21 }
        { fadd f11, f22, f23 }
)";
    const sched::ResBound r = res(m, body);
    CHECK(r.cycles == 1.2);
    CHECK(r.ii() == 2);
    CHECK(r.binds == "FPRF read ports 6/5 = 1.20");
}

TEST_CASE("ResMII on ic: three FPUs, and the FPRF's three write ports", "[bounds]") {
    const isa::Machine m = isa::load_machine("ic");
    // 7 float multiplies on fpu0..fpu2: 7 / 3 (the 7 FPRF writes over 3 ports tie; slots come first).
    const char* mul7 = R"(
        { fmul f1, f10, f11 ; fmul f2, f10, f12 ; fmul f3, f10, f13 }
        { fmul f4, f11, f12 ; fmul f5, f11, f13 ; fmul f6, f12, f13 }
        { fmul f7, f1, f2 }
)";
    const sched::ResBound a = res(m, mul7);
    CHECK(a.cycles == Approx(7.0 / 3));
    CHECK(a.ii() == 3);
    CHECK(a.binds == "slots {fpu0,fpu1,fpu2}: 7 ops / 3 = 2.33");
    // 3 fmuls would fill the FPUs in one cycle, but the load on iu0 is a fourth FPRF write: 4 / 3.
    const char* load = R"(
        { flw f4, 0(r1) ; fmul f1, f10, f11 ; fmul f2, f10, f12 }
        { fmul f3, f10, f13 }
)";
    const sched::ResBound b = res(m, load);
    CHECK(b.cycles == Approx(4.0 / 3));
    CHECK(b.ii() == 2);
    CHECK(b.binds == "FPRF write ports 4/3 = 1.33");
}

TEST_CASE("ResMII: reads packed into bundles of few read ports", "[bounds]") {
    const isa::Machine m = isa::parse_machine("inherits = \"ic\"\nname = \"ic-3rp\"\n[registers.float]\nread_ports = 3\n",
                                              "ic-3rp.toml");
    // Five float adds (2 reads each): 10 reads / 3 = 3.33, but no two adds share a bundle (4
    // reads > 3), so 5 bundles.
    const char* body = R"(
        fadd f1, f10, f11
        fadd f2, f10, f12
        fadd f3, f11, f12
        fadd f4, f11, f13
        fadd f5, f12, f13
)";
    const sched::ResBound a = res(m, body);
    CHECK(a.cycles == 5);
    CHECK(a.binds == "FPRF read ports 10/3 packed: 5 ops read more than half of them = 5");
    // Five negations (1 read each) fill the read each add leaves: 15 / 3 = 5 bundles still.
    const char* negs = R"(
        { fadd f1, f10, f11 ; fneg f6, f10 }
        { fadd f2, f10, f12 ; fneg f7, f11 }
        { fadd f3, f11, f12 ; fneg f8, f12 }
        { fadd f4, f11, f13 ; fneg f9, f13 }
        { fadd f5, f12, f13 ; fneg f14, f10 }
)";
    const sched::ResBound b = res(m, negs);
    CHECK(b.cycles == 5);
    CHECK(b.binds == "FPRF read ports 15/3 = 5");
    // On ic's 7 read ports the same adds pack 3 to a bundle: the reads bind no more than slots.
    CHECK(res(isa::load_machine("ic"), body).ii() == 2);
}

TEST_CASE("ResMII on seq: one unit takes every op", "[bounds]") {
    const isa::Machine m = isa::load_machine("seq");
    const char* body = R"(
        lw r2, 0(r1)
        add r3, r3, r2
        addi r1, r1, 4
        bne r1, r5, loop
)";
    const sched::ResBound r = res(m, body);
    CHECK(r.cycles == 4);
    CHECK(r.binds == "slots {u0}: 4 ops / 1 = 4");
    // nothing to issue: no bound, II 1
    const sched::ResBound none = sched::res_mii(m, {});
    CHECK(none.cycles == 0);
    CHECK(none.binds.empty());
    CHECK(none.ii() == 1);
}

TEST_CASE("region RecMII on os: a float recurrence through a multiply and an add", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // f1 is read live-in by the fmul and written last by the fadd: fmul (1) + fadd (1) = 2. r1's
    // chain is the addi alone (1); f3 is written before it is read, so it carries nothing.
    const char* body = R"(
        { flw f3, 0(r1) ; addi r1, r1, 4 }
        { fmul f4, f1, f3 }
        { fadd f1, f4, f5 }
        bne r1, r9, loop
)";
    const auto ops = body_ops(m, body);
    const sched::RecBound r = sched::region_rec_mii(m, ops);
    CHECK(r.cycles == 2);
    CHECK(r.reg == "f1");
    REQUIRE(r.chain.size() == 2);
    CHECK(ops[r.chain[0]].instr.info().mnemonic == "fmul");
    CHECK(ops[r.chain[1]].instr.info().mnemonic == "fadd");
    CHECK(r.binds == "f1: fmul (1) -> fadd (1) = 2 cycles");
}

TEST_CASE("region RecMII on seq: the 4-cycle divide", "[bounds]") {
    const isa::Machine m = isa::load_machine("seq");
    // f1 = (f1 * f4) / f2 each pass: fmul (1) + fdiv (4) = 5. The nops keep the exposed pipeline
    // legal around the back edge and count nothing.
    const char* body = R"(
        fmul f3, f1, f4
        fdiv f1, f3, f2
        nop
        nop
        nop
        bne r1, r5, loop
)";
    const auto ops = body_ops(m, body);
    REQUIRE(ops.size() == 3);
    const sched::RecBound r = sched::region_rec_mii(m, ops);
    CHECK(r.cycles == 5);
    CHECK(r.binds == "f1: fmul (1) -> fdiv (4) = 5 cycles");
    CHECK(sched::res_mii(m, instrs(ops)).cycles == 3);
}

TEST_CASE("region RecMII on ic: no carried register, no bound", "[bounds]") {
    const isa::Machine m = isa::load_machine("ic");
    // Every register read is either never written (f10, f11, r1) or written first (f1).
    const char* body = R"(
        { fmul f1, f10, f11 }
        { fadd f2, f1, f10 ; fsw f1, 0(r1) }
)";
    const sched::RecBound r = sched::region_rec_mii(m, body_ops(m, body));
    CHECK(r.cycles == 0);
    CHECK(r.binds.empty());
    CHECK(r.chain.empty());
}

TEST_CASE("region RecMII on ic: the longest of two chains to the last write", "[bounds]") {
    const isa::Machine m = isa::load_machine("ic");
    // r2 is read live-in twice, and both chains end in its one write: addi (1) -> add (1) = 2,
    // and mul (1) -> add (1) -> add (1) = 3, which binds.
    const char* body = R"(
        { mul r3, r2, r2 }
        { addi r7, r2, 1 }
        { add r4, r3, r3 }
        { add r2, r4, r7 }
)";
    const sched::RecBound r = sched::region_rec_mii(m, body_ops(m, body));
    CHECK(r.cycles == 3);
    CHECK(r.binds == "r2: mul (1) -> add (1) -> add (1) = 3 cycles");
}

TEST_CASE("region RecMII counts a recurrence through memory", "[bounds]") {
    const isa::Machine m = isa::load_machine("os");
    // Each pass stores at 4(r1) what the next pass loads at 0(r1 + 4): lw -> addi -> sw -> lw.
    // No register carries a value round (r3 is written before it is read), so only the memory
    // edge closes the circuit.
    const char* body = R"(
        { lw r3, 0(r1) }
        { addi r3, r3, 1 }
        { sw r3, 4(r1) ; addi r1, r1, 4 }
)";
    const auto ops = body_ops(m, body);
    const sched::RecBound r = sched::region_rec_mii(m, ops);
    const int lw = static_cast<int>(m.latency_of(ops[0].instr.info()));
    CHECK(r.cycles == lw + 1 + 1);
    CHECK(r.reg == "memory true r1");
    CHECK(r.binds == fmt::format("memory true r1: lw ({}) -> addi (1) -> sw (1) = {} cycles", lw, lw + 2));
}
