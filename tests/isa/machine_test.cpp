// Machine descriptions: presets carry the paper's facts; bad files give file:line:col errors;
// a description inherits another and lists only its differences.
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

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

using nesshi::test::TempDir;

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

// A slot name prefixes pinned ops in sources and disassembly: "iu 0" made disassembly that could
// not be assembled again.
TEST_CASE("slot names are identifiers, with their location") {
    for (const char* bad : {"iu 0", "iu:0", "0iu", "iu.0", "$iu", "iu-0"}) {
        INFO(bad);
        CHECK(error_of(replace(kGood, "name = \"u0\"", fmt::format("name = \"{}\"", bad)))
                  .rfind(fmt::format("t.toml:22:8: error: slot name '{}' is not an identifier", bad), 0) == 0);
    }
    CHECK(error_of(replace(kGood, "name = \"u0\"", "name = \"_u_0\"")) == "no error");
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

// The -real presets as flat files, before they inherited from os, ic and seq (comments
// dropped, every key as it was): the derived presets must load to exactly these machines.
namespace {
struct Flat {
    const char* name;
    const char* text;
};
const Flat kFlatReal[] = {
    {"os-real", R"TOML(name = "os-real"
description = "Object search: 2 IU + 2 FPU, pipelined multi-cycle units (for latency studies)"
branch_penalty = 1

[registers.int]
count = 128
read_ports = 5
write_ports = 2

[registers.float]
count = 128
read_ports = 5
write_ports = 2

[latency]
alu = 1
mul = 3
fadd = 3
fmul = 3
fdiv = 12
load = 2
store = 1
branch = 1
fifo = 1
misc = 1

[[slot]]
name = "iu0"
accepts = ["alu", "mul", "load", "store", "branch", "fifo", "misc"]

[[slot]]
name = "iu1"
accepts = ["alu", "mul", "load", "store", "fifo", "misc"]

[[slot]]
name = "fpu0"
accepts = ["fadd", "fmul", "fdiv", "fifo", "misc"]

[[slot]]
name = "fpu1"
accepts = ["fadd", "fmul", "fdiv", "fifo", "misc"]

[[memory]]
name = "sram"
base = 0x00000000
size = 0x00200000
)TOML"},
    {"ic-real", R"TOML(name = "ic-real"
description = "Intersection: 1 IU + 3 FPU, pipelined multi-cycle units (for latency studies)"
branch_penalty = 1

[registers.int]
count = 128
read_ports = 5
write_ports = 2

[registers.float]
count = 128
read_ports = 7
write_ports = 3

[latency]
alu = 1
mul = 3
fadd = 3
fmul = 3
fdiv = 12
load = 2
store = 1
branch = 1
fifo = 1
misc = 1

[[slot]]
name = "iu0"
accepts = ["alu", "mul", "load", "store", "branch", "fifo", "misc"]

[[slot]]
name = "fpu0"
accepts = ["fadd", "fmul", "fdiv", "fifo", "misc"]

[[slot]]
name = "fpu1"
accepts = ["fadd", "fmul", "fdiv", "fifo", "misc"]

[[slot]]
name = "fpu2"
accepts = ["fadd", "fmul", "fdiv", "fifo", "misc"]

[[memory]]
name = "resident"
base = 0x00400000
size = 0x00100000

[[memory]]
name = "global"
base = 0x10000000
size = 0x04000000
cached = true
)TOML"},
    {"seq-real", R"TOML(name = "seq-real"
description = "Sequential: 1 general unit, pipelined multi-cycle units (for latency studies)"
branch_penalty = 1

[registers.int]
count = 128
read_ports = 3
write_ports = 1

[registers.float]
count = 128
read_ports = 3
write_ports = 1

[latency]
alu = 1
mul = 3
fadd = 3
fmul = 3
fdiv = 12
load = 2
store = 1
branch = 1
fifo = 1
misc = 1

[[slot]]
name = "u0"
accepts = ["alu", "mul", "fadd", "fmul", "fdiv", "load", "store", "branch", "fifo", "misc"]

[[memory]]
name = "sram"
base = 0x00000000
size = 0x00200000

[[memory]]
name = "resident"
base = 0x00400000
size = 0x00100000

[[memory]]
name = "local"
base = 0x00800000
size = 0x00800000

[[memory]]
name = "global"
base = 0x10000000
size = 0x04000000
cached = true
)TOML"},
};
} // namespace

TEST_CASE("the -real presets inherit and load exactly as their flat descriptions did") {
    for (const auto& f : kFlatReal) {
        INFO(f.name);
        CHECK(preset_text(f.name).find("inherits = ") != std::string_view::npos);
        const Machine flat = parse_machine(f.text, fmt::format("builtin:{}", f.name));
        const Machine now = load_machine(f.name);
        CHECK(now.name == flat.name);
        CHECK(now.description == flat.description);
        CHECK(now.source == flat.source);
        CHECK(now.branch_penalty == flat.branch_penalty);
        REQUIRE(now.slots.size() == flat.slots.size());
        for (size_t i = 0; i < now.slots.size(); ++i) {
            CHECK(now.slots[i].name == flat.slots[i].name);
            CHECK(now.slots[i].classes == flat.slots[i].classes);
        }
        for (int c = 0; c < kNumOpClasses; ++c) CHECK(now.latency[c] == flat.latency[c]);
        for (int r = 0; r < kNumRegFiles; ++r) {
            CHECK(now.regs[r].count == flat.regs[r].count);
            CHECK(now.regs[r].read_ports == flat.regs[r].read_ports);
            CHECK(now.regs[r].write_ports == flat.regs[r].write_ports);
        }
        REQUIRE(now.memories.size() == flat.memories.size());
        for (size_t i = 0; i < now.memories.size(); ++i) {
            CHECK(now.memories[i].name == flat.memories[i].name);
            CHECK(now.memories[i].base == flat.memories[i].base);
            CHECK(now.memories[i].size == flat.memories[i].size);
            CHECK(now.memories[i].latency == flat.memories[i].latency);
            CHECK(now.memories[i].cached == flat.memories[i].cached);
        }
        CHECK(now == flat); // catches a field added to Machine later
        CHECK(now.fingerprint() == flat.fingerprint());
    }
}

TEST_CASE("preset fingerprints are those committed objects carry") {
    // Recorded before the -real presets inherited; an object assembled for a preset keeps
    // loading only while these hold.
    const std::pair<const char*, uint64_t> pinned[] = {
        {"os", 0xd07f596a35b6f415ull},      {"os-real", 0xce1bd575e2288019ull},
        {"ic", 0x7676278a30bdf879ull},      {"ic-real", 0xa3b2302b7b652ad3ull},
        {"seq", 0x361bc1388cfb438cull},     {"seq-real", 0xe01521521babdb50ull},
    };
    for (const auto& [name, fp] : pinned) {
        INFO(name);
        CHECK(load_machine(name).fingerprint() == fp);
    }
    const ObjectFile obj =
        read_object_file(NESSHI_SOURCE_DIR "/tests/iss/programs/port_conflict_branch.o");
    CHECK(obj.machine_fingerprint == load_machine(obj.machine).fingerprint());
}

namespace {

std::string load_error(const std::string& name_or_path) {
    try {
        load_machine(name_or_path);
    } catch (const MachineError& e) {
        return e.what();
    }
    return "no error";
}

const std::string kPresetList = "presets: ic, ic-real, os, os-real, seq, seq-real";
} // namespace

TEST_CASE("a description inherits a preset and lists only its differences", "[inherits]") {
    const Machine m = parse_machine(R"(inherits = "os"
name = "os-wide"
[registers.float]
write_ports = 3
[latency]
fdiv = 8
)",
                                    "t.toml");
    Machine want = load_machine("os");
    REQUIRE_FALSE(want.description.empty());
    want.name = "os-wide";
    want.description = ""; // never inherited
    want.source = "t.toml";
    want.regs[int(RegFile::Float)].write_ports = 3; // read_ports and count stay the parent's
    want.latency[int(OpClass::FDiv)] = 8;           // every other class stays the parent's
    CHECK(m == want);
    CHECK(m.fingerprint() != load_machine("os").fingerprint());
}

TEST_CASE("a child's [[slot]] or [[memory]] entries replace the parent's whole array",
          "[inherits]") {
    const std::string fpu = "accepts = [\"fadd\", \"fmul\", \"fdiv\", \"fifo\", \"misc\"]\n";
    const Machine m = parse_machine(
        "inherits = \"ic\"\nname = \"ic-4fpu\"\ndescription = \"one FPU more\"\n"
        "branch_penalty = 2\n"
        "[[slot]]\nname = \"iu0\"\n"
        "accepts = [\"alu\", \"mul\", \"load\", \"store\", \"branch\", \"fifo\", \"misc\"]\n"
        "[[slot]]\nname = \"fpu0\"\n" + fpu + "[[slot]]\nname = \"fpu1\"\n" + fpu +
            "[[slot]]\nname = \"fpu2\"\n" + fpu + "[[slot]]\nname = \"fpu3\"\n" + fpu +
            "[[memory]]\nname = \"resident\"\nbase = 0x00400000\nsize = 0x00200000\n",
        "t.toml");
    const Machine ic = load_machine("ic");
    REQUIRE(m.slots.size() == 5);
    for (size_t i = 0; i < ic.slots.size(); ++i) CHECK(m.slots[i] == ic.slots[i]);
    CHECK(m.slots[4].name == "fpu3");
    REQUIRE(m.memories.size() == 1); // the parent's "global" is gone
    CHECK(m.memories[0].size == 2u << 20);
    CHECK(m.regs == ic.regs);
    CHECK(m.latency == ic.latency);
    CHECK(m.branch_penalty == 2);
    CHECK(m.description == "one FPU more");
    // Without its own branch_penalty the child keeps the parent's.
    CHECK(parse_machine("inherits = \"os-real\"\nname = \"x\"\n", "t.toml").branch_penalty == 1);
}

TEST_CASE("what a child gives is checked as in a flat file", "[inherits]") {
    CHECK(error_of("inherits = \"os\"\nname = \"x\"\n[registers.int]\ncount = 0\n") ==
          "t.toml:3:1: error: a register file needs at least one register");
    CHECK(error_of("inherits = \"os\"\nname = \"x\"\n[latency]\nfdiv = 0\n") ==
          "t.toml:4:8: error: latencies are at least 1 cycle");
    CHECK(error_of("inherits = \"os\"\nname = \"x\"\n[latency]\nvec = 1\n") ==
          "t.toml:4:7: error: unknown operation class 'vec'");
    // A replaced slot array must accept every class by itself.
    CHECK(error_of("inherits = \"os\"\nname = \"x\"\n[[slot]]\nname = \"u\"\n"
                   "accepts = [\"alu\"]\n") ==
          "t.toml:3:1: error: no slot accepts operation class 'mul'");
    CHECK(error_of("inherits = \"os\"\ndescription = \"no name\"\n") ==
          "t.toml:1:1: error: missing key 'name'");
}

TEST_CASE("an unknown parent is an error at the inherits line", "[inherits]") {
    CHECK(error_of("name = \"x\"\ninherits = \"nope\"\n") ==
          "t.toml:2:12: error: unknown parent machine 'nope': no such preset or file nope (" +
              kPresetList + ")");
    CHECK(error_of("name = \"x\"\ninherits = 3\n") ==
          "t.toml:2:12: error: 'inherits' must be a string");
    try { // a preset reaches only presets
        parse_machine("inherits = \"nope.toml\"\nname = \"x\"\n", "builtin:x");
        FAIL("expected an error");
    } catch (const MachineError& e) {
        CHECK(std::string(e.what()) ==
              "builtin:x:1:12: error: unknown parent machine 'nope.toml': no such preset (" +
                  kPresetList + ")");
    }
}

TEST_CASE("a parent file is found relative to the inheriting file", "[inherits]") {
    TempDir dir("nesshi-isa-relative");
    const std::string d = dir.path.string();
    dir.file("base/mid.toml", "inherits = \"os\"\nname = \"mid\"\n[latency]\nfadd = 2\n");
    const std::string child = dir.file(
        "variants/child.toml",
        "inherits = \"../base/mid.toml\"\nname = \"child\"\n[latency]\nfmul = 2\n");
    const Machine m = load_machine(child); // the working directory is not the file's
    const Machine os = load_machine("os");
    CHECK(m.name == "child");
    CHECK(m.source == child);
    CHECK(m.latency[int(OpClass::FAdd)] == 2);
    CHECK(m.latency[int(OpClass::FMul)] == 2);
    CHECK(m.latency[int(OpClass::Alu)] == 1);
    CHECK(m.slots == os.slots);
    CHECK(m.memories == os.memories);
    // An absolute path is taken as it is.
    const std::string abs = dir.file(
        "elsewhere/abs.toml", fmt::format("inherits = \"{}/base/mid.toml\"\nname = \"abs\"\n", d));
    CHECK(load_machine(abs).latency[int(OpClass::FAdd)] == 2);
    // A preset name wins over a file of that name beside the child; ./os names the file.
    dir.file("variants/os", "not toml at all = =\n");
    dir.file("variants/preset.toml", "inherits = \"os\"\nname = \"p\"\n");
    CHECK(load_machine(d + "/variants/preset.toml").slots == os.slots);
    dir.file("variants/file.toml", "inherits = \"./os\"\nname = \"f\"\n");
    CHECK(load_error(d + "/variants/file.toml").rfind(d + "/variants/os:1:", 0) == 0);
    // An error inside a parent is reported in the parent's file.
    dir.file("base/bad.toml", "inherits = \"os\"\nname = \"bad\"\nwidth = 4\n");
    dir.file("variants/of_bad.toml", "inherits = \"../base/bad.toml\"\nname = \"c\"\n");
    CHECK(load_error(d + "/variants/of_bad.toml") ==
          d + "/base/bad.toml:3:9: error: unknown key 'width' in the top level");
    CHECK(load_error(d + "/variants/orphan.toml").find("no such machine preset or file") !=
          std::string::npos);
    dir.file("variants/orphan.toml", "inherits = \"gone.toml\"\nname = \"o\"\n");
    CHECK(load_error(d + "/variants/orphan.toml") ==
          fmt::format("{0}/variants/orphan.toml:1:12: error: unknown parent machine 'gone.toml': "
                      "no such preset or file {0}/variants/gone.toml ({1})",
                      d, kPresetList));
}

TEST_CASE("inheritance cycles and chains deeper than the limit are errors", "[inherits]") {
    TempDir dir("nesshi-isa-cycle");
    const std::string d = dir.path.string();
    dir.file("a.toml", "inherits = \"b.toml\"\nname = \"a\"\n");
    dir.file("b.toml", "name = \"b\"\ninherits = \"a.toml\"\n");
    CHECK(load_error(d + "/a.toml") ==
          fmt::format("{0}/b.toml:2:12: error: machine inheritance cycle: {0}/a.toml -> "
                      "{0}/b.toml -> {0}/a.toml",
                      d));
    dir.file("self.toml", "inherits = \"self.toml\"\nname = \"s\"\n");
    CHECK(load_error(d + "/self.toml") ==
          fmt::format("{0}/self.toml:1:12: error: machine inheritance cycle: {0}/self.toml -> "
                      "{0}/self.toml",
                      d));
    // l0 -> l1 -> ... -> l9 -> os: l(i) has 10 - i ancestors.
    for (int i = 0; i < 10; ++i)
        dir.file(fmt::format("l{}.toml", i),
                  fmt::format("inherits = \"{}\"\nname = \"l{}\"\n",
                              i == 9 ? std::string("os") : fmt::format("l{}.toml", i + 1), i));
    static_assert(kMaxInheritDepth == 8);
    CHECK(load_machine(d + "/l2.toml").slots == load_machine("os").slots); // 8 ancestors
    CHECK(load_error(d + "/l1.toml") ==
          d + "/l9.toml:1:12: error: machine inheritance deeper than 8 levels");
}

// Machine files are about 1 KB with keys two levels deep. A header or dotted key of ~31,000
// components used to overflow the stack inside toml++ (it bounds nested values, not key depth);
// such texts, and files above base::kMaxMachineFileBytes, are refused before parsing.
TEST_CASE("implausibly deep or large descriptions are refused before parsing", "[bad-input]") {
    std::string deep = "[a";
    for (int i = 0; i < 31000; ++i) deep += ".a";
    CHECK(error_of(deep + "]\n") == "t.toml:1:35: error: more than 16 '.' on one line: the keys of a machine "
                                    "description nest a few levels, not this deep");
    CHECK(error_of("name = \"x\"\n" + deep.substr(1) + " = 1\n").rfind("t.toml:2:34: error: more than 16 '.'", 0) == 0);
    // Dots inside strings and comments are not keys.
    const std::string dots(40, '.');
    CHECK(error_of(replace(kGood, "name = \"tiny\"", "name = \"tiny\" # " + dots)) == "no error");
    CHECK(error_of(replace(kGood, "name = \"tiny\"", "name = \"tiny\"\ndescription = \"" + dots + "\"")) ==
          "no error");
    CHECK(error_of(replace(kGood, "name = \"tiny\"", "name = \"tiny\"\ndescription = '''\n" + dots + "\n'''")) ==
          "no error");
    CHECK(error_of(std::string((1 << 20) + 1, '#')) ==
          "t.toml:1:1: error: description too large (1048577 bytes; the limit is 1048576)");

    TempDir dir("nesshi-isa-plausible");
    const std::string big = dir.file("big.toml", std::string((1 << 20) + 1, '#'));
    CHECK(load_error(big) == big + ": error: file too large (1048577 bytes; the limit is 1048576)");
    CHECK(load_error("/dev/zero") == "/dev/zero: error: not a regular file");
    CHECK(load_error(dir.path.string()) == dir.path.string() + ": error: is a directory");
    const std::string child = dir.file("child.toml", "inherits = \"/dev/zero\"\nname = \"c\"\n");
    CHECK(load_error(child) == "/dev/zero: error: not a regular file");
}
