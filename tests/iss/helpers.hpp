// Test helpers: build objects from operations directly (no assembler needed).
#pragma once

#include "iss/processor.hpp"

#include "isa/bundle_check.hpp"
#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <catch2/catch.hpp>

#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

namespace nesshi::iss::test {

// Zeroes the fields an operation does not use (the decoder rejects anything else).
inline isa::Instr clean(isa::Instr in) {
    unsigned used = isa::used_fields(in.info());
    auto has = [&](isa::Field f) { return (used >> static_cast<int>(f)) & 1u; };
    if (!has(isa::Field::Rd)) in.rd = 0;
    if (!has(isa::Field::Rs1)) in.rs1 = 0;
    if (!has(isa::Field::Rs2)) in.rs2 = 0;
    if (!has(isa::Field::Rs3)) in.rs3 = 0;
    if (!has(isa::Field::Imm)) in.imm = 0;
    return in;
}

// An operation by mnemonic; fields as in the encoding (rd, rs1, rs2, imm, rs3).
inline isa::Instr op(std::string_view m, uint8_t rd = 0, uint8_t rs1 = 0, uint8_t rs2 = 0, uint32_t imm = 0,
                     uint8_t rs3 = 0) {
    isa::Instr in;
    auto code = isa::find_opcode(m);
    REQUIRE(code);
    in.opcode = *code;
    in.rd = rd;
    in.rs1 = rs1;
    in.rs2 = rs2;
    in.imm = imm;
    in.rs3 = rs3;
    return clean(in);
}

using Bundle = std::vector<isa::Instr>;

// Slots are assigned automatically (or kept as given when `pinned`); labels are (name, bundle) pairs; data sections optional.
inline isa::ObjectFile make_object(const isa::Machine& m, std::vector<Bundle> bundles,
                                   std::vector<std::pair<std::string, uint32_t>> labels = {},
                                   std::vector<isa::DataSection> data = {}, bool pinned = false) {
    isa::ObjectFile obj;
    obj.machine = m.name;
    obj.machine_fingerprint = m.fingerprint();
    obj.files = {"test.s"};
    uint32_t line = 1;
    for (Bundle& b : bundles) {
        std::vector<int> pins(b.size(), -1);
        if (pinned)
            for (size_t i = 0; i < b.size(); ++i) pins[i] = b[i].slot;
        REQUIRE(isa::assign_slots(m, b, pins));
        for (size_t i = 0; i < b.size(); ++i) obj.code.push_back(isa::encode(b[i], i + 1 == b.size()));
        obj.lines.push_back({0, line++});
    }
    for (auto& [name, value] : labels) obj.symbols.push_back({name, isa::SymbolKind::Code, value, false});
    obj.data = std::move(data);
    return obj;
}

inline std::unique_ptr<Processor> make_proc(const std::string& machine, std::vector<Bundle> bundles,
                                            Engine e = Engine::Fast,
                                            std::vector<std::pair<std::string, uint32_t>> labels = {},
                                            std::vector<isa::DataSection> data = {}) {
    isa::Machine m = isa::load_machine(machine);
    return std::make_unique<Processor>(load_program(make_object(m, std::move(bundles), std::move(labels),
                                                                std::move(data)), m), e);
}

inline uint16_t R(int n) { return flat_reg(isa::RegFile::Int, n); }
inline uint16_t F(int n) { return flat_reg(isa::RegFile::Float, n); }

} // namespace nesshi::iss::test
