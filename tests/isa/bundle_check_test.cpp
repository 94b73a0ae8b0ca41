// The bundle checker: slots, ports and duplicate writes; and slot assignment.
#include "isa/bundle_check.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <random>

using namespace nesshi::isa;

namespace {
Instr mk(std::string_view m, uint8_t rd = 0, uint8_t rs1 = 0, uint8_t rs2 = 0, uint32_t imm = 0) {
    Instr in;
    in.opcode = *find_opcode(m);
    in.rd = rd;
    in.rs1 = rs1;
    in.rs2 = rs2;
    in.imm = imm;
    return in;
}

std::vector<Violation> check_auto(const Machine& m, std::vector<Instr> ops) {
    std::vector<int> pins(ops.size(), -1);
    REQUIRE(assign_slots(m, ops, pins));
    return check_bundle(m, ops);
}
} // namespace

TEST_CASE("three FPRF writes in one cycle exceed the OS but fit the IC") {
    std::vector<Instr> ops = {mk("fadd", 1, 2, 3), mk("fadd", 4, 5, 6), mk("flw", 7, 1, 0, 0)};
    auto v = check_auto(load_machine("os"), ops);
    REQUIRE(v.size() == 1);
    CHECK(v[0].rule == Rule::WritePorts);
    CHECK(v[0].op == 2);
    CHECK(v[0].other == 0);
    CHECK(v[0].message == "bundle needs more than 2 FPRF write ports in cycle +1; os has 2");
    // The IC has 1 IU (for flw) and 3 FPUs, and 3 FPRF write ports.
    CHECK(check_auto(load_machine("ic"), ops).empty());
}

TEST_CASE("read ports are counted across the bundle") {
    Machine os = load_machine("os");
    // Two fadds read 4 FPRF registers; each fsw reads one more: 6 > 5.
    std::vector<Instr> ops = {mk("fadd", 1, 2, 3), mk("fadd", 4, 5, 6), mk("fsw", 0, 1, 7, 0)};
    CHECK(check_auto(os, ops).empty());
    ops.push_back(mk("fsw", 0, 1, 8, 4));
    auto v = check_auto(os, ops);
    REQUIRE(v.size() == 1);
    CHECK(v[0].rule == Rule::ReadPorts);
    CHECK(v[0].op == 3);
    CHECK(v[0].other == 0);
    CHECK(v[0].message == "bundle needs 6 FPRF read ports; os has 5");
}

TEST_CASE("slots reject classes they do not accept") {
    Machine os = load_machine("os");
    std::vector<Instr> ops = {mk("fadd", 1, 2, 3)};
    ops[0].slot = 0; // iu0
    auto v = check_bundle(os, ops);
    REQUIRE(v.size() == 1);
    CHECK(v[0].rule == Rule::SlotClass);
    CHECK(v[0].message == "slot iu0 does not accept 'fadd' (class fadd)");
}

TEST_CASE("duplicate writes in one cycle, but not in different cycles") {
    Machine os = load_machine("os");
    auto v = check_auto(os, {mk("add", 1, 2, 3), mk("sub", 1, 2, 3)});
    REQUIRE(v.size() == 1);
    CHECK(v[0].rule == Rule::DupWrite);
    CHECK(check_auto(os, {mk("fmul", 1, 2, 3), mk("fdiv", 1, 2, 3)}).empty());
}

TEST_CASE("register numbers are checked against the machine") {
    Machine m = load_machine("os");
    m.regs[0].count = 32;
    auto v = check_auto(m, {mk("add", 40, 2, 3)});
    REQUIRE(v.size() == 1);
    CHECK(v[0].message == "register r40 out of range: os has 32 registers");
}

TEST_CASE("slot assignment finds a matching when one exists") {
    Machine os = load_machine("os");
    // Branch only fits iu0; the add must move to iu1 even though it comes first.
    std::vector<Instr> ops = {mk("add", 1, 2, 3), mk("beqz", 0, 1, 0, 0)};
    std::vector<int> pins = {-1, -1};
    REQUIRE(assign_slots(os, ops, pins));
    CHECK(ops[0].slot == 1);
    CHECK(ops[1].slot == 0);
    // Three integer ops cannot fit two IUs.
    std::vector<Instr> three = {mk("add"), mk("add"), mk("add")};
    std::vector<int> pins3 = {-1, -1, -1};
    CHECK_FALSE(assign_slots(os, three, pins3));
    // A pin is honoured.
    std::vector<Instr> pinned = {mk("fadd", 1, 2, 3)};
    std::vector<int> pin = {3};
    REQUIRE(assign_slots(os, pinned, pin));
    CHECK(pinned[0].slot == 3);
}

TEST_CASE("bundle_fits answers as check_bundle finds nothing, on random bundles") {
    // Random ops, slots and registers (some out of range), on the presets and on files with
    // fewer ports, so that every rule both passes and fails many times.
    std::vector<Machine> machines;
    for (const char* name : {"os", "ic", "os-real", "seq"}) machines.push_back(load_machine(name));
    for (Machine m : {load_machine("os"), load_machine("ic")}) {
        for (RegFileDesc& rf : m.regs) rf.read_ports = 2, rf.write_ports = 1;
        machines.push_back(m);
    }
    std::mt19937 rng(7);
    std::array<int, 2> outcomes{};
    for (int trial = 0; trial < 20000; ++trial) {
        const Machine& m = machines[rng() % machines.size()];
        std::vector<Instr> ops(1 + rng() % (m.slots.size() + 1));
        for (Instr& in : ops) {
            in.opcode = static_cast<Opcode>(rng() % kNumOps);
            in.slot = static_cast<uint8_t>(rng() % (m.slots.size() + 1));
            for (uint8_t* r : {&in.rd, &in.rs1, &in.rs2, &in.rs3}) *r = static_cast<uint8_t>(rng() % 8 == 0 ? rng() % 128 : rng() % 6);
        }
        if (rng() % 2) {
            std::vector<int> pins(ops.size(), -1);
            assign_slots(m, ops, pins);
        }
        const bool fits = bundle_fits(m, ops);
        INFO("trial " << trial << " on " << m.name);
        CHECK(fits == check_bundle(m, ops).empty());
        ++outcomes[fits];
    }
    CHECK(outcomes[0] > 1000);
    CHECK(outcomes[1] > 1000);
}
