// Machine descriptions: presets carry the paper's facts; bad files give file:line:col errors.
#include "isa/machine.hpp"

#include <catch2/catch.hpp>

using namespace nesshi::isa;

TEST_CASE("presets hold the paper's machine facts") {
    Machine os = load_machine("os");
    CHECK(os.slots.size() == 4);
    CHECK(os.regs[0].count == 128);
    CHECK(os.regs[0].read_ports == 5);
    CHECK(os.regs[0].write_ports == 2);
    CHECK(os.regs[1].read_ports == 5);
    CHECK(os.regs[1].write_ports == 2);
    REQUIRE(os.memories.size() == 1);
    CHECK(os.memories[0].size == 2u << 20);
    Machine ic = load_machine("ic");
    CHECK(ic.slots.size() == 4);
    CHECK(ic.regs[1].read_ports == 7);
    CHECK(ic.regs[1].write_ports == 3);
    int fpus = 0;
    for (const auto& s : ic.slots) fpus += s.accepts(OpClass::FAdd);
    CHECK(fpus == 3);
    Machine seq = load_machine("seq");
    REQUIRE(seq.slots.size() == 1);
    for (int c = 0; c < kNumOpClasses; ++c) CHECK(seq.slots[0].accepts(OpClass(c)));
    for (auto name : {"os", "ic", "seq"}) {
        Machine m = load_machine(name);
        CHECK(m.latency[int(OpClass::Alu)] == 1);
        CHECK(m.latency[int(OpClass::FAdd)] == 1);
        CHECK(m.latency[int(OpClass::FMul)] == 1);
        CHECK(m.latency[int(OpClass::Load)] == 1);
        CHECK(m.latency[int(OpClass::FDiv)] > 1);
        Machine real = load_machine(std::string(name) + "-real");
        CHECK(real.latency[int(OpClass::FAdd)] > 1);
        CHECK(real.slots.size() == m.slots.size());
        CHECK(real.fingerprint() != m.fingerprint());
    }
}

TEST_CASE("fingerprints are stable and sensitive") {
    CHECK(load_machine("os").fingerprint() == load_machine("os").fingerprint());
    CHECK(load_machine("os").fingerprint() != load_machine("ic").fingerprint());
}

namespace {
const char* kGood = R"(name = "tiny"
[registers.int]
count = 16
read_ports = 2
write_ports = 1
[registers.float]
count = 16
read_ports = 2
write_ports = 1
[latency]
alu = 1
mul = 1
fadd = 1
fmul = 1
fdiv = 2
load = 1
store = 1
branch = 1
fifo = 1
misc = 1
[[slot]]
name = "u0"
accepts = ["alu", "mul", "fadd", "fmul", "fdiv", "load", "store", "branch", "fifo", "misc"]
[[memory]]
name = "m"
base = 0
size = 1024
)";

std::string error_of(const std::string& text) {
    try {
        parse_machine(text, "t.toml");
    } catch (const MachineError& e) {
        return e.what();
    }
    return "no error";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
    auto pos = s.find(from);
    REQUIRE(pos != std::string::npos);
    return s.replace(pos, from.size(), to);
}
} // namespace

TEST_CASE("a user description parses") {
    Machine m = parse_machine(kGood, "t.toml");
    CHECK(m.name == "tiny");
    CHECK(m.regs[0].count == 16);
    CHECK(m.latency[int(OpClass::FDiv)] == 2);
}

TEST_CASE("malformed descriptions are rejected with file:line:col") {
    CHECK(error_of(replace(kGood, "count = 16\nread_ports = 2\nwrite_ports = 1\n[registers.float]",
                           "count = 200\nread_ports = 2\nwrite_ports = 1\n[registers.float]")) ==
          "t.toml:3:9: error: 'count' = 200 is out of range 0..128");
    CHECK(error_of(replace(kGood, "fdiv = 2", "fdiv = 0")) ==
          "t.toml:15:8: error: latencies are at least 1 cycle");
    CHECK(error_of(replace(kGood, "\"fifo\", \"misc\"]", "\"fifo\", \"misc\", \"vector\"]")) ==
          "t.toml:23:93: error: unknown operation class (known: alu, mul, fadd, fmul, fdiv, "
          "load, store, branch, fifo, misc)");
    CHECK(error_of(replace(kGood, "\"fifo\", \"misc\"]", "\"misc\"]")) ==
          "t.toml:21:1: error: no slot accepts operation class 'fifo'");
    CHECK(error_of(replace(kGood, "size = 1024", "size = 1022")) ==
          "t.toml:24:1: error: memory base and size must be multiples of 4, size > 0");
    CHECK(error_of(replace(kGood, "name = \"tiny\"", "name = \"tiny\"\nwidth = 4")) ==
          "t.toml:2:9: error: unknown key 'width' in the top level");
    CHECK(error_of(replace(kGood, "[latency]", "[latency\n")).rfind("t.toml:10:", 0) == 0);
    CHECK(error_of(replace(kGood, "mul = 1\n", "")) == "t.toml:10:1: error: missing key 'mul'");
}

TEST_CASE("an unknown preset or missing file names the presets") {
    try {
        load_machine("no-such-machine");
        FAIL("expected an error");
    } catch (const MachineError& e) {
        CHECK(std::string(e.what()) ==
              "no-such-machine: error: no such machine preset or file (presets: ic, ic-real, os, "
              "os-real, seq, seq-real)");
    }
}
