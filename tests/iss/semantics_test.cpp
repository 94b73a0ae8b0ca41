// Every operation against a plain C++ reference evaluator on random inputs and float edge cases
// (NaN, +-inf, -0, subnormals: the ISS keeps subnormals, it does not flush them).
#include "helpers.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace nesshi;
using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {

float fl(uint32_t x) { return std::bit_cast<float>(x); }
uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }
// Arithmetic results: a NaN is always the canonical quiet NaN (the ISA's rule).
uint32_t arith(float x) { return std::isnan(x) ? 0x7fc00000u : bits(x); }
int32_t sg(uint32_t x) { return int32_t(x); }

// The reference: written independently of isa::kOps, one plain statement per operation.
std::optional<uint32_t> reference(std::string_view m, uint32_t a, uint32_t b, uint32_t c, uint32_t imm) {
    if (m == "add") return a + b;
    if (m == "sub") return a - b;
    if (m == "and") return a & b;
    if (m == "or") return a | b;
    if (m == "xor") return a ^ b;
    if (m == "sll") return a << (b % 32);
    if (m == "srl") return a >> (b % 32);
    if (m == "sra") return uint32_t(sg(a) >> (b % 32));
    if (m == "slt") return sg(a) < sg(b) ? 1u : 0u;
    if (m == "sltu") return a < b ? 1u : 0u;
    if (m == "seq") return a == b ? 1u : 0u;
    if (m == "sne") return a != b ? 1u : 0u;
    if (m == "min") return uint32_t(std::min(sg(a), sg(b)));
    if (m == "max") return uint32_t(std::max(sg(a), sg(b)));
    if (m == "addi") return a + imm;
    if (m == "andi") return a & imm;
    if (m == "ori") return a | imm;
    if (m == "xori") return a ^ imm;
    if (m == "slli") return a << (imm % 32);
    if (m == "srli") return a >> (imm % 32);
    if (m == "srai") return uint32_t(sg(a) >> (imm % 32));
    if (m == "slti") return sg(a) < sg(imm) ? 1u : 0u;
    if (m == "li" || m == "fli") return imm;
    if (m == "mov" || m == "fmov" || m == "movif" || m == "movfi") return a;
    if (m == "sel" || m == "fsel") return a != 0 ? b : c;
    if (m == "mul") return uint32_t(uint64_t(a) * uint64_t(b));
    if (m == "fadd") return arith(fl(a) + fl(b));
    if (m == "fsub") return arith(fl(a) - fl(b));
    if (m == "fmul") return arith(fl(a) * fl(b));
    if (m == "fdiv") return arith(fl(a) / fl(b));
    if (m == "fsqrt") return arith(std::sqrt(fl(a)));
    if (m == "fmin") return fl(a) < fl(b) ? a : b;
    if (m == "fmax") return fl(a) > fl(b) ? a : b;
    if (m == "fabs") return a & 0x7fffffffu;
    if (m == "fneg") return a ^ 0x80000000u;
    if (m == "flt") return fl(a) < fl(b) ? 1u : 0u;
    if (m == "fle") return fl(a) <= fl(b) ? 1u : 0u;
    if (m == "feq") return fl(a) == fl(b) ? 1u : 0u;
    if (m == "itof") return bits(float(sg(a)));
    if (m == "ftoi") {
        float x = fl(a);
        if (std::isnan(x)) return 0u;
        if (x >= 2147483648.0f) return uint32_t(INT32_MAX);
        if (x <= -2147483648.0f) return uint32_t(INT32_MIN);
        return uint32_t(int32_t(std::trunc(x)));
    }
    return std::nullopt;
}

const std::vector<uint32_t> kEdges = {
    0x00000000, 0x80000000, 0x3f800000, 0xbf800000, 0x7f800000, 0xff800000, 0x7fc00000, 0xffc00001,
    0x7f800001, 0x00000001, 0x80000001, 0x007fffff, 0x807fffff, 0x00800000, 0x7f7fffff, 0xff7fffff,
    0x4f000000, 0xcf000000, 0x4effffff, 0x00000020, 0x0000001f, 0xffffffff, 0x7fffffff, 0x3effffff,
    0x40490fdb, 0x00400000};

// Input values: edge cases against each other, then random bits and random floats.
std::vector<std::array<uint32_t, 3>> inputs(uint32_t seed) {
    std::vector<std::array<uint32_t, 3>> out;
    std::mt19937 rng(seed);
    for (uint32_t a : kEdges)
        for (size_t i = 0; i < kEdges.size(); i += 3) out.push_back({a, kEdges[i], kEdges[(i + 5) % kEdges.size()]});
    std::uniform_real_distribution<float> real(-1000.0f, 1000.0f);
    for (int i = 0; i < 150; ++i) {
        out.push_back({uint32_t(rng()), uint32_t(rng()), uint32_t(rng())});
        out.push_back({bits(real(rng)), bits(real(rng)), uint32_t(rng() % 2)});
    }
    return out;
}

uint16_t flat_of(const isa::Operand& o, uint8_t n) {
    return flat_reg(o.kind == isa::OperandKind::FloatReg ? isa::RegFile::Float : isa::RegFile::Int, n);
}

} // namespace

TEST_CASE("every compute operation matches the reference evaluator") {
    for (int code = 0; code < isa::kNumOps; ++code) {
        const isa::OpInfo& info = isa::kOps[code];
        if (info.kind != isa::Kind::Compute) continue;
        INFO("operation " << info.mnemonic);
        // Sources r/f 1, 2, 3 by field; the result goes to r/f 10.
        isa::Instr in;
        in.opcode = isa::Opcode(code);
        in.rd = 10;
        in.rs1 = 1;
        in.rs2 = 2;
        in.rs3 = 3;
        uint16_t regs[3] = {kNoReg, kNoReg, kNoReg};
        uint16_t dst = kNoReg;
        bool has_imm = false;
        for (int k = 0; k < info.num_operands; ++k) {
            const isa::Operand& o = info.operands[k];
            if (o.is_dest) dst = flat_of(o, 10);
            else if (o.field == isa::Field::Rs1) regs[0] = flat_of(o, 1);
            else if (o.field == isa::Field::Rs2) regs[1] = flat_of(o, 2);
            else if (o.field == isa::Field::Rs3) regs[2] = flat_of(o, 3);
            else has_imm = true;
        }
        REQUIRE(dst != kNoReg);
        static const isa::Machine seq = isa::load_machine("seq");
        std::shared_ptr<const Program> prog;
        uint32_t prog_imm = 0;
        for (const auto& v : inputs(uint32_t(code) + 1)) {
            in.imm = has_imm ? v[1] : 0;
            if (!prog || prog_imm != in.imm) { // one program per immediate value
                prog = load_program(make_object(seq, {{clean(in)}, {op("halt")}}), seq);
                prog_imm = in.imm;
            }
            auto proc = std::make_unique<Processor>(prog);
            for (int s = 0; s < 3; ++s)
                if (regs[s] != kNoReg) proc->set_reg(regs[s], v[s]);
            REQUIRE(proc->run() == Status::Halted);
            auto want = reference(info.mnemonic, v[0], v[1], v[2], in.imm);
            REQUIRE(want.has_value()); // a new operation needs a reference entry
            INFO("inputs 0x" << std::hex << v[0] << " 0x" << v[1] << " 0x" << v[2]);
            CHECK(proc->reg(dst) == *want);
        }
    }
}

TEST_CASE("subnormals are kept, not flushed") {
    auto p = make_proc("seq", {{op("fmul", 1, 2, 3)}, {op("fadd", 4, 2, 2)}, {op("halt")}});
    p->set_reg(F(2), 0x00000001); // the smallest subnormal
    p->set_reg(F(3), bits(0.5f));
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(F(1)) == 0x00000000);  // rounds to even: 0
    CHECK(p->reg(F(4)) == 0x00000002);  // 2 x smallest subnormal, not flushed
}

TEST_CASE("loads and stores: widths, sign extension, little-endian") {
    isa::DataSection data{0x100, {0x81, 0x82, 0x83, 0x84, 0, 0, 0x80, 0x3f}};
    auto p = make_proc("seq",
                       {{op("li", 1, 0, 0, 0x100)},
                        {op("lw", 2, 1, 0, 0)}, {op("lh", 3, 1, 0, 2)}, {op("lhu", 4, 1, 0, 2)},
                        {op("lb", 5, 1, 0, 3)}, {op("lbu", 6, 1, 0, 3)}, {op("flw", 1, 1, 0, 4)},
                        {op("sw", 0, 1, 2, 8)}, {op("sh", 0, 1, 2, 12)}, {op("sb", 0, 1, 2, 14)},
                        {op("fsw", 0, 1, 1, 16)}, {op("halt")}},
                       Engine::Checked, {}, {data});
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(R(2)) == 0x84838281u);
    CHECK(p->reg(R(3)) == 0xffff8483u);
    CHECK(p->reg(R(4)) == 0x00008483u);
    CHECK(p->reg(R(5)) == 0xffffff84u);
    CHECK(p->reg(R(6)) == 0x00000084u);
    CHECK(p->reg(F(1)) == 0x3f800000u);
    uint32_t v = 0;
    REQUIRE(p->memory().peek(0x108, 4, v));
    CHECK(v == 0x84838281u);
    REQUIRE(p->memory().peek(0x10c, 4, v));
    CHECK(v == 0x00818281u); // sh writes 0x8281 at +12, sb writes 0x81 at +14
    REQUIRE(p->memory().peek(0x110, 4, v));
    CHECK(v == 0x3f800000u);
}

TEST_CASE("a load in the same bundle as a store reads the old memory") {
    isa::DataSection data{0x100, {1, 0, 0, 0}};
    auto p = make_proc("os", {{op("li", 1, 0, 0, 0x100), op("li", 2, 0, 0, 7)},
                              {op("sw", 0, 1, 2, 0), op("lw", 3, 1, 0, 0)},
                              {op("lw", 4, 1, 0, 0)}, {op("halt")}},
                       Engine::Checked, {}, {data});
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(R(3)) == 1);
    CHECK(p->reg(R(4)) == 7);
}

TEST_CASE("branches: each condition, taken and not taken") {
    struct Case { const char* m; uint32_t a, b; bool taken; };
    for (Case c : {Case{"beq", 5, 5, true}, Case{"beq", 5, 6, false}, Case{"bne", 5, 6, true},
                   Case{"blt", uint32_t(-1), 0, true}, Case{"blt", 0, uint32_t(-1), false},
                   Case{"bge", 3, 3, true}, Case{"bltu", 0, uint32_t(-1), true}, Case{"bltu", uint32_t(-1), 0, false},
                   Case{"bgeu", uint32_t(-1), 0, true}, Case{"beqz", 0, 0, true}, Case{"beqz", 1, 0, false},
                   Case{"bnez", 1, 0, true}}) {
        INFO(c.m << " " << c.a << " " << c.b);
        auto p = make_proc("seq", {{op(c.m, 0, 1, 2, 3)}, {op("li", 9, 0, 0, 1)}, {op("halt")}, {op("halt")}});
        p->set_reg(R(1), c.a);
        p->set_reg(R(2), c.b);
        REQUIRE(p->run() == Status::Halted);
        CHECK(p->reg(R(9)) == (c.taken ? 0u : 1u));
        CHECK(p->pc() == (c.taken ? 3u : 2u));
    }
}

TEST_CASE("jmp, jal and jr, a taken branch costs the machine's branch penalty") {
    auto prog = std::vector<Bundle>{{op("jal", 5, 0, 0, 3)}, {op("halt")}, {op("halt")},
                                    {op("addi", 6, 5, 0, 10)}, {op("jr", 0, 6)}, {op("halt")},
                                    {op("halt")}, {op("halt")}, {op("halt")}, {op("halt")}, {op("halt")},
                                    {op("jmp", 0, 0, 0, 1)}};
    auto p = make_proc("os", prog);
    REQUIRE(p->run() == Status::Halted);
    CHECK(p->reg(R(5)) == 1);  // address of the bundle after jal
    CHECK(p->pc() == 1);
    CHECK(p->cycle() == 5);    // jal, addi, jr, jmp, halt; os has no penalty
    auto r = make_proc("os-real", prog);
    REQUIRE(r->run() == Status::Halted);
    CHECK(r->cycle() == 5 + 3); // three taken transfers, one bubble each
    CHECK(r->counters().bubble_cycles == 3);
}

TEST_CASE("send and recv move words through channels") {
    auto p = make_proc("os", {{op("recv", 1, 0, 0, 0)}, {op("addi", 1, 1, 0, 1)}, {op("send", 0, 1, 0, 2)},
                              {op("frecv", 3, 0, 0, 0)}, {op("fsend", 0, 3, 0, 2)}, {op("halt")}});
    QueueChannel in, out;
    in.feed(41);
    in.feed(0x3f800000);
    p->attach_channel(0, &in);
    p->attach_channel(2, &out);
    REQUIRE(p->run() == Status::Halted);
    CHECK(out.drain_all() == std::vector<uint32_t>{42, 0x3f800000});
}
