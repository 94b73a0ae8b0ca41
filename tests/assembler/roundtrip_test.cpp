// Round trips: every operation and operand range through encode -> decode -> print -> parse ->
// encode, and every example/kernel through asm -> dis -> asm with byte-identical objects.
#include "support.hpp"

#include "lexer.hpp"
#include "operands.hpp"

#include "isa/bundle_check.hpp"
#include "isa/printer.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <random>

using namespace nesshi;

namespace {

// Parses one printed operation ("slot: mnemonic operands") with the assembler's own parser.
std::optional<isa::Instr> parse_printed(const std::string& text, const isa::Machine& m, std::string& diag) {
    assembler::SourceSet sources;
    sources.add("op.s", text);
    assembler::Diagnostics diags(sources);
    auto toks = assembler::lex_line(text);
    REQUIRE(toks.size() >= 3);
    REQUIRE(toks[1].is(":"));
    int slot = m.slot_index(toks[0].text);
    std::span<const assembler::Token> op(toks.data() + 2, toks.size() - 2);
    auto rec = assembler::parse_op(op, 0, 1, m, diags);
    if (rec) {
        assembler::Resolver none = [](const assembler::Token&, std::string&) { return std::optional<int64_t>(); };
        if (!assembler::resolve_imm(*rec, none, size_t{1} << 33, diags)) rec.reset();
    }
    diag = diags.render();
    if (!rec || slot < 0) return std::nullopt;
    rec->instr.slot = uint8_t(slot);
    return rec->instr;
}

std::vector<uint32_t> imm_values(isa::OperandKind k, std::mt19937& rng) {
    std::vector<uint32_t> v;
    switch (k) {
    case isa::OperandKind::FloatImm:
        v = {0u, 0x80000000u, 0x3f800000u, 0xc0200000u, 0x7f800000u, 0xff800000u, 0x7fc00000u, 0x7fa00001u,
             0xffc00123u, 1u, 0x007fffffu, 0x00800000u, 0x7f7fffffu, 0xff7fffffu, 0x40490fdbu, 0x3dcccccdu};
        for (int i = 0; i < 2000; ++i) v.push_back(uint32_t(rng()));
        break;
    case isa::OperandKind::Target:
    case isa::OperandKind::Channel: v = {0u, 1u, 2u, 7u, 1000u, 0x7fffffffu, 0x80000000u, 0xffffffffu}; break;
    default:
        v = {0u, 1u, 4u, 0xffffffffu, 0xfffffffcu, 0x7fffffffu, 0x80000000u, 12345u, uint32_t(-4096)};
        for (int i = 0; i < 64; ++i) v.push_back(uint32_t(rng()));
        break;
    }
    return v;
}

} // namespace

TEST_CASE("every operation and operand range survives encode-decode-print-parse-encode", "[roundtrip]") {
    const isa::Machine m = isa::load_machine("seq"); // one slot that accepts every class
    std::mt19937 rng(1234);
    size_t checked = 0;
    for (int opc = 0; opc < isa::kNumOps; ++opc) {
        const isa::OpInfo& info = isa::kOps[size_t(opc)];
        std::vector<isa::Instr> variants;
        isa::Instr base;
        base.opcode = isa::Opcode(opc);
        variants.push_back(base);
        for (int k = 0; k < info.num_operands; ++k) {
            const isa::Operand& o = info.operands[size_t(k)];
            auto vary_reg = [&](isa::Field f) {
                for (int r = 0; r < 128; ++r) {
                    isa::Instr in = base;
                    in.rd = f == isa::Field::Rd ? uint8_t(r) : uint8_t(5);
                    in.rs1 = f == isa::Field::Rs1 ? uint8_t(r) : uint8_t(6);
                    in.rs2 = f == isa::Field::Rs2 ? uint8_t(r) : uint8_t(7);
                    in.rs3 = f == isa::Field::Rs3 ? uint8_t(r) : uint8_t(8);
                    variants.push_back(in);
                }
            };
            if (o.kind == isa::OperandKind::IntReg || o.kind == isa::OperandKind::FloatReg) vary_reg(o.field);
            if (o.kind == isa::OperandKind::Mem) vary_reg(isa::Field::Rs1);
            if (o.field == isa::Field::Imm)
                for (uint32_t v : imm_values(o.kind, rng)) {
                    isa::Instr in = base;
                    in.imm = v;
                    variants.push_back(in);
                }
        }
        for (isa::Instr in : variants) {
            // Clear fields the operation does not use (the decoder insists on zeros).
            unsigned used = isa::used_fields(info);
            if (!(used & (1u << int(isa::Field::Rd)))) in.rd = 0;
            if (!(used & (1u << int(isa::Field::Rs1)))) in.rs1 = 0;
            if (!(used & (1u << int(isa::Field::Rs2)))) in.rs2 = 0;
            if (!(used & (1u << int(isa::Field::Rs3)))) in.rs3 = 0;
            if (used & (1u << int(isa::Field::Rs3)) || !(used & (1u << int(isa::Field::Imm)))) in.imm = 0;
            uint64_t word = isa::encode(in, true);
            isa::DecodeResult d = isa::decode(word);
            REQUIRE(d.ok);
            std::string text = isa::format_instr_slotted(d.instr, m);
            std::string diag;
            auto back = parse_printed(text, m, diag);
            INFO(text << "\n" << diag);
            REQUIRE(back);
            REQUIRE(isa::encode(*back, true) == word);
            ++checked;
        }
    }
    CHECK(checked > 10000);
}

TEST_CASE("asm -> dis -> asm is byte-identical for every example", "[roundtrip]") {
    auto programs = test::asm_programs();
    REQUIRE(programs.size() >= 5);
    for (const auto& p : programs) {
        std::string text = test::read_text(p);
        isa::Machine m = isa::load_machine(test::header_machine(text));
        std::string rel = std::filesystem::relative(p, NESSHI_SOURCE_DIR).string();
        auto a = assembler::assemble_file(p.string(), m, {});
        INFO(rel << "\n" << a.diagnostics);
        REQUIRE(a.ok);
        CHECK(a.diagnostics.empty()); // examples assemble without warnings
        std::string dis = assembler::disassemble(a.object, m);
        auto b = assembler::assemble_string(dis, "dis.s", m, {});
        INFO(dis << "\n" << b.diagnostics);
        REQUIRE(b.ok);
        CHECK(isa::write_object(a.object) == isa::write_object(b.object));
    }
}
