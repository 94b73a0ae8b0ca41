// sched/block.hpp: straight-line blocks list-scheduled into bundles, then shortened by the
// constraint model. A property test draws random blocks (registers reused on purpose, so anti and
// output dependences are common, and memory accesses that may alias) and checks on the ISS that
// the bundles compute what the sequential block computes, on the ideal and the -real presets.
#include "sched/block.hpp"

#include "assembler/assembler.hpp"
#include "base/error.hpp"
#include "isa/machine.hpp"
#include "isa/ops.hpp"
#include "iss/differential.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

using namespace nesshi;

namespace {

isa::Instr instr(const isa::Machine& m, const std::string& op) {
    const auto r = assembler::assemble_string("        " + op + "\n        halt\n", "t.s", m, {});
    REQUIRE(r.ok);
    return isa::decode_bundles(r.object).front().front();
}

// A block of `n` ops over f1-f6 and r2-r6 (few registers: values are overwritten while still
// needed elsewhere), with loads and stores to one buffer.
std::vector<std::string> random_block(std::mt19937_64& rng, int n) {
    auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    auto f = [&] { return fmt::format("f{}", pick(1, 6)); };
    auto r = [&] { return fmt::format("r{}", pick(2, 6)); };
    std::vector<std::string> ops;
    for (int k = 0; k < n; ++k) {
        switch (pick(0, 9)) {
        case 0: ops.push_back(fmt::format("fadd {}, {}, {}", f(), f(), f())); break;
        case 1: ops.push_back(fmt::format("fmul {}, {}, {}", f(), f(), f())); break;
        case 2: ops.push_back(fmt::format("fdiv {}, {}, {}", f(), f(), f())); break;
        case 3: ops.push_back(fmt::format("add {}, {}, {}", r(), r(), r())); break;
        case 4: ops.push_back(fmt::format("addi {}, {}, {}", r(), r(), pick(-3, 3))); break;
        case 5: ops.push_back(fmt::format("fle {}, {}, {}", r(), f(), f())); break;
        case 6: ops.push_back(fmt::format("fsel {}, {}, {}, {}", f(), r(), f(), f())); break;
        case 7: ops.push_back(fmt::format("flw {}, buf+{}(r1)", f(), 4 * pick(0, 7))); break;
        case 8: ops.push_back(fmt::format("fsw {}, buf+{}(r1)", f(), 4 * pick(0, 7))); break;
        default: ops.push_back(fmt::format("mul {}, {}, {}", r(), r(), r())); break;
        }
    }
    return ops;
}

// The program around a block: the block itself (`packed`, markers kept) or its sequential
// meaning (each op followed by enough nops for it to land). A block ending in `jmp after` jumps
// to code that reads its registers at once: its results must land by then.
std::string program(const isa::Machine& m, const std::vector<std::string>& ops, bool sequential) {
    std::string s = fmt::format("        .data 0x{:x}\nbuf:    .float 1.5, -2, 3.25, 0.5, 7, -1, 2, 9\n        .text\n"
                                "        li r1, 0\n        li r2, 3\n        li r3, -5\n        li r4, 7\n        li r5, 1\n        li r6, 2\n",
                                m.memories.front().base + 0x100);
    for (int k = 1; k <= 6; ++k) s += fmt::format("        fli f{}, {}.5\n", k, k - 3);
    for (std::uint32_t k = 0; k < m.max_latency(); ++k) s += "        nop\n"; // a block starts with nothing in flight
    if (!sequential) s += "#pack begin\n";
    for (const std::string& op : ops) {
        s += "        " + op + "\n";
        if (sequential)
            for (std::uint32_t k = 1; k < m.max_latency(); ++k) s += "        nop\n";
    }
    if (!sequential) s += "#pack end\n";
    if (!ops.empty() && ops.back().starts_with("jmp"))
        s += "after:  fadd f7, f1, f2\n        fadd f7, f3, f4\n        fadd f7, f5, f6\n"
             "        add r7, r2, r3\n        add r7, r4, r5\n        add r7, r6, r6\n";
    for (std::uint32_t k = 0; k < m.max_latency(); ++k) s += "        nop\n"; // the last results land
    return s + "        halt\n";
}

} // namespace

TEST_CASE("a divide's latency is filled with independent work, its user waits", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("os");
    const std::vector<isa::Instr> ops = {instr(m, "fdiv f1, f2, f3"), instr(m, "fadd f4, f1, f1"), instr(m, "add r1, r2, r3")};
    const auto b = sched::list_schedule(m, ops);
    REQUIRE(b.size() == 5);
    CHECK(b[0] == std::vector<int>{0, 2});
    CHECK(b[1].empty());
    CHECK(b[4] == std::vector<int>{1});
}

TEST_CASE("an overwrite waits for the reader of the old value, and a branch stays last", "[unit][sched][block]") {
    // (The name has no ';': catch_discover_tests splits a name there, and CTest then ran nothing.)
    const isa::Machine m = isa::load_machine("os");
    // fadd reads f1 in bundle 0; the fli overwriting f1 may share that bundle but not precede it.
    // The jump may share it too: every earlier op has latency 1 and lands before the jump's
    // target issues, as the kernels' bodies end ({ jr ; fsel ; fmin }).
    const std::vector<isa::Instr> ops = {instr(m, "fadd f4, f1, f2"), instr(m, "fli f1, 2.0"), instr(m, "jmp 0")};
    const auto b = sched::list_schedule(m, ops);
    REQUIRE(b.size() == 1);
    CHECK(b[0] == std::vector<int>{0, 1, 2});
    // A 4-cycle divide before the jump: the jump waits until it lands (bundle 3 of 0..3).
    const std::vector<isa::Instr> slow = {instr(m, "fdiv f4, f1, f2"), instr(m, "jmp 0")};
    const auto c = sched::list_schedule(m, slow);
    REQUIRE(c.size() >= 2);
    CHECK(c.back() == std::vector<int>{1});
}

TEST_CASE("a jump's taken-branch bubble lets results land after the block", "[unit][sched][block]") {
    // os-real's jump costs one bubble cycle, in which nothing issues: a divide may issue one
    // bundle later than on a machine without one and still land before the target's first bundle.
    const isa::Machine m = isa::load_machine("os-real");
    REQUIRE(m.branch_penalty == 1);
    const std::vector<isa::Instr> jump = {instr(m, "fdiv f4, f1, f2"), instr(m, "jmp 0")};
    const std::size_t lat = m.latency_of(jump[0].info());
    CHECK(sched::list_schedule(m, jump).size() == lat - 1);
    CHECK(sched::block_schedule(m, jump, sched::kBlockSearchNodes).bundles.size() == lat - 1);
    // A conditional branch falls through without a bubble: its block waits as before.
    const std::vector<isa::Instr> branch = {instr(m, "fdiv f4, f1, f2"), instr(m, "bnez r1, 0")};
    CHECK(sched::list_schedule(m, branch).size() == lat);
    // The target reads the quotient in its first bundle: the assembler's hazard check agrees.
    const std::string text = "#pack begin\n        fdiv f4, f1, f2\n        jmp next\n#pack end\nnext:   fadd f5, f4, f4\n        halt\n";
    const auto a = assembler::assemble_string(sched::pack_source(text, "t.pk", m).text, "t.s", m, {});
    INFO(a.diagnostics);
    CHECK(a.ok);
}

TEST_CASE("an overwrite with a long latency still waits for the reader of the old value", "[unit][sched][block]") {
    // The assembler refuses a read while a write of the register is in flight, even one that
    // would land after the read: the fdiv overwriting f1 may not issue before the fadd that reads
    // the old f1, however late that fadd waits for f3. (The dependence's distance is 1 - latency,
    // which only shapes the priorities: an op is placed after every op it depends on. Making it 0
    // changes kernels, and made a random IC machine's sphere 1.64x its bound.)
    const isa::Machine m = isa::load_machine("os-real");
    REQUIRE(m.latency_of(instr(m, "fdiv f1, f8, f9").info()) > 2);
    const std::vector<isa::Instr> ops = {instr(m, "fdiv f3, f8, f9"), instr(m, "fadd f4, f1, f3"), instr(m, "fdiv f1, f8, f9")};
    const auto b = sched::list_schedule(m, ops);
    auto at = [&](int op) {
        for (std::size_t k = 0; k < b.size(); ++k)
            if (std::find(b[k].begin(), b[k].end(), op) != b[k].end()) return static_cast<int>(k);
        return -1;
    };
    REQUIRE(at(1) > 0);
    CHECK(at(2) >= at(1));
}

TEST_CASE("FIFO words of a bundle take slots in program order", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("os");
    const std::vector<isa::Instr> ops = {instr(m, "recv r1, 0"), instr(m, "fadd f1, f2, f3"), instr(m, "frecv f4, 0")};
    const std::vector<int> slots = sched::ordered_slots(m, ops);
    REQUIRE(slots.size() == 3);
    CHECK(slots[0] < slots[2]);
    CHECK(m.slots[static_cast<std::size_t>(slots[1])].accepts(isa::OpClass::FAdd));
    CHECK(sched::ordered_slots(m, std::vector<isa::Instr>(5, ops[1])).empty()); // 5 ops, 4 slots
}

TEST_CASE("two writes of one register in one bundle take slots in program order", "[unit][sched][block]") {
    // Found by fuzzing (crashes/iss/two-writes-one-bundle): on os-real recv (1 cycle) and lw
    // (2 cycles) of r3 may share a bundle, the lw landing last, so the recv takes the lower slot.
    const isa::Machine m = isa::load_machine("os-real");
    const std::vector<isa::Instr> ops = {instr(m, "recv r3, 1"), instr(m, "lw r3, 0(r1)")};
    const std::vector<int> slots = sched::ordered_slots(m, ops);
    REQUIRE(slots.size() == 2);
    CHECK(slots[0] < slots[1]);
    const std::string text = "        .data 0x100\nbuf:    .space 16\n        .text\n        li r1, buf\n        nop\n        nop\n"
                             "#pack begin\n        recv r3, 1\n        lw r3, 0(r1)\n#pack end\n        halt\n";
    const sched::PackResult r = sched::pack_source(text, "t.pk", m);
    const auto a = assembler::assemble_string(r.text, "t.s", m, {});
    INFO(r.text << a.diagnostics);
    CHECK(a.ok);
}

TEST_CASE("a block that falls through ends when its last result lands", "[unit][sched][block]") {
    // Found by fuzzing (crashes/schedule/fallthrough-in-flight): the next code read a result
    // still in flight. A 4-cycle divide alone takes 4 bundles, then its user may issue.
    const isa::Machine m = isa::load_machine("os");
    const std::vector<isa::Instr> ops = {instr(m, "fdiv f1, f2, f3")};
    CHECK(sched::list_schedule(m, ops).size() == m.latency_of(ops[0].info()));
    const std::string text = "#pack begin\n        fdiv f1, f2, f3\n#pack end\n        fadd f4, f1, f1\n        halt\n";
    const auto a = assembler::assemble_string(sched::pack_source(text, "t.pk", m).text, "t.s", m, {});
    INFO(a.diagnostics);
    CHECK(a.ok);
}

TEST_CASE("pack_source keeps what is outside the blocks and reports each block", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("ic");
    const std::string text = "# machine: ic\n        li r1, 1\n#pack begin\n        fadd f1, f2, f3   # one\n\n"
                             "        fmul f4, f5, f6\n#pack end\n        halt\n";
    const sched::PackResult r = sched::pack_source(text, "t.pk", m);
    CHECK(r.text == "# machine: ic\n        li r1, 1\n        { fadd f1, f2, f3 ; fmul f4, f5, f6 }\n        halt\n");
    REQUIRE(r.blocks.size() == 1);
    CHECK(r.blocks[0].line == 3);
    CHECK(r.blocks[0].ops == 2);
    CHECK(r.blocks[0].bundles == 1);
}

TEST_CASE("#if machine sections keep one preset's code, #else every other machine's", "[unit][sched][block]") {
    const std::string text = "        li r1, 1\n#if machine os\n        li r2, 2\n#pack begin\n        add r3, r1, r2\n"
                             "#pack end\n#else\n        li r2, 3\n#endif\n        halt\n";
    CHECK(sched::pack_source(text, "t.pk", isa::load_machine("os")).text ==
          "        li r1, 1\n        li r2, 2\n        { add r3, r1, r2 }\n        halt\n");
    CHECK(sched::pack_source(text, "t.pk", isa::load_machine("os-real")).text == "        li r1, 1\n        li r2, 3\n        halt\n");
    // machine_sections blanks the lines it drops, so line numbers stay those of the file.
    CHECK(sched::machine_sections(text, "t.pk", isa::load_machine("os-real")) ==
          "        li r1, 1\n\n\n\n\n\n\n        li r2, 3\n\n        halt\n");
    // A section open at the end, a nested one or one naming no preset is an error at its line.
    CHECK_THROWS_WITH(sched::pack_source("#if machine os\n        halt\n", "t.pk", isa::load_machine("os")),
                      Catch::Contains("t.pk:1: error: '#if machine' is never closed by '#endif'"));
    CHECK_THROWS_WITH(sched::pack_source("#if machine os\n#if machine ic\n#endif\n", "t.pk", isa::load_machine("os")),
                      Catch::Contains("t.pk:2: error: '#if machine' inside another"));
    CHECK_THROWS_WITH(sched::pack_source("#if machine nosuch\n#endif\n", "t.pk", isa::load_machine("os")),
                      Catch::Contains("names no preset machine ('nosuch')"));
}

TEST_CASE("pack_source places a block's virtual registers on the declared range", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("seq"); // one unit: the bundles keep program order
    // %a dies at the first read of it, and its f10 goes to the back of the free list: %c takes
    // the front (f12); %b dies at the fmul, whose %d then takes f10; %d is never read.
    const std::string text = "#pack virtual f10-f12   # temporaries\n#pack begin\n        fmul %a, f1, f2\n"
                             "        fadd %b, f1, f3\n        fadd %c, %a, f4\n        fmul %d, %b, %c\n"
                             "        fsw %c, 0(r1)\n#pack end\n        halt\n";
    const sched::PackResult r = sched::pack_source(text, "t.pk", m);
    CHECK(r.text.find("#pack") == std::string::npos);
    CHECK(r.text.find("{ fmul f10, f1, f2 }") != std::string::npos);
    CHECK(r.text.find("{ fadd f11, f1, f3 }") != std::string::npos);
    CHECK(r.text.find("{ fadd f12, f10, f4 }") != std::string::npos);
    CHECK(r.text.find("{ fmul f10, f11, f12 }") != std::string::npos);
    CHECK(r.text.find("{ fsw f12, 0(r1) }") != std::string::npos);
    // Errors name the line.
    CHECK_THROWS_WITH(sched::pack_source("#pack begin\n        fadd %a, f1, f2\n#pack end\n", "t.pk", m),
                      "t.pk:2: error: %a: no '#pack virtual' range of float registers before this block");
    CHECK_THROWS_WITH(sched::pack_source("#pack virtual f10-f12\n#pack begin\n        fadd f1, %a, f2\n#pack end\n", "t.pk", m),
                      Catch::Contains("t.pk:3: error: %a is read before this block writes it"));
    CHECK_THROWS_WITH(sched::pack_source("#pack virtual f10-f10\n#pack begin\n        fadd %a, f1, f2\n"
                                         "        fadd %b, f1, f2\n        fadd f3, %a, %b\n#pack end\n", "t.pk", m),
                      "t.pk:4: error: %b: every register of the '#pack virtual' range is live here");
    CHECK_THROWS_WITH(sched::pack_source("#pack virtual f10-r12\n", "t.pk", m),
                      Catch::Contains("t.pk:1: error: '#pack virtual' takes one register range of one file"));
}

TEST_CASE("malformed blocks are errors with a location", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("os");
    CHECK_THROWS_WITH(sched::pack_source("#pack begin\n        nop\n", "t.pk", m),
                      "t.pk:1: error: '#pack begin' is never closed by '#pack end'");
    CHECK_THROWS_WITH(sched::pack_source("        nop\n#pack end\n", "t.pk", m), "t.pk:2: error: '#pack end' without '#pack begin'");
    CHECK_THROWS_AS(sched::pack_source("#pack begin\n        frob r1\n#pack end\n", "t.pk", m), base::Error);
    // A hazard in the hand-written code is reported at its line in the file (not in the padded
    // sequential text the scheduler assembles).
    CHECK_THROWS_WITH(sched::pack_source("#pack begin\n        fadd f4, f5, f6\n#pack end\n        fdiv f1, f2, f3\n"
                                         "        fadd f7, f1, f1\n        halt\n", "t.pk", m),
                      Catch::Contains("t.pk:5:9: error: f1 is read before its new value lands"));
}

// Findings Q1 (two branches in a block: the scheduler never returned) and Q2 (an op after a
// branch or halt moved into its bundle) of the robustness campaign (issue 24).
TEST_CASE("a control operation anywhere but last in a block is an error at its line", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("os");
    CHECK_THROWS_WITH(sched::pack_source("#pack begin\n        li r1, 4\n        jr r13\n        jr r13\n#pack end\n", "t.pk", m),
                      Catch::StartsWith("t.pk:3: error: 'jr' before the end of a '#pack' block"));
    CHECK_THROWS_WITH(sched::pack_source("#pack begin\n        jr r13\n        addi r1, r1, 4\n#pack end\n", "t.pk", m),
                      Catch::StartsWith("t.pk:2: error: 'jr' before the end"));
    CHECK_THROWS_WITH(sched::pack_source("\n#pack begin\n        halt\n        li r1, 1\n#pack end\n", "t.pk", m),
                      Catch::StartsWith("t.pk:3: error: 'halt' before the end"));
    // list_schedule itself refuses such a block rather than loop.
    const std::vector<isa::Instr> two = {instr(m, "jr r13"), instr(m, "jr r13")};
    CHECK_THROWS_AS(sched::list_schedule(m, two), std::invalid_argument);
    // Last is fine, and it stays last.
    const sched::PackResult ok = sched::pack_source("#pack begin\n        li r1, 4\n        jr r13\n#pack end\n", "t.pk", m);
    CHECK(ok.text.find("jr r13") != std::string::npos);
}

TEST_CASE("random blocks: the bundles compute what the sequential block computes", "[unit][sched][block]") {
    std::vector<std::string> regs;
    for (int k = 1; k <= 6; ++k) regs.push_back(fmt::format("f{}", k));
    for (int k = 2; k <= 6; ++k) regs.push_back(fmt::format("r{}", k));
    int blocks = 0, shorter = 0, proven = 0;
    for (const char* name : {"os", "ic", "seq", "os-real", "ic-real"}) {
        const isa::Machine m = isa::load_machine(name);
        std::mt19937_64 rng(std::hash<std::string>{}(name));
        for (int trial = 0; trial < 40; ++trial) {
            auto ops = random_block(rng, 4 + trial % 20);
            if (trial % 2) ops.push_back("jmp after"); // its results may land in the jump's bubble
            INFO(name << " trial " << trial << ":\n" << program(m, ops, true));
            const sched::PackResult packed = sched::pack_source(program(m, ops, false), "t.pk", m);
            const auto a = assembler::assemble_string(program(m, ops, true), "seq.s", m, {});
            const auto b = assembler::assemble_string(packed.text, "packed.s", m, {});
            INFO(packed.text << b.diagnostics);
            REQUIRE(a.ok);
            REQUIRE(b.ok);
            REQUIRE(packed.blocks.size() == 1);
            CHECK(packed.blocks[0].bundles <= static_cast<int>(ops.size() * m.max_latency()));
            iss::DiffOptions d;
            d.registers = regs;
            d.randomize_data = false;
            CHECK(iss::run_differential(a.object, b.object, m, d) == std::nullopt);
            ++blocks;
            const sched::BlockStats& st = packed.blocks[0];
            CHECK(st.bundles <= st.list_bundles);
            CHECK(st.fewest <= st.bundles);
            CHECK(st.shortest == (st.bundles == st.fewest));
            shorter += st.bundles < st.list_bundles;
            proven += st.shortest;
        }
    }
    CHECK(blocks == 200);
    // The constraint model is at work: it shortens some list schedules and proves most blocks
    // shortest (the bundles above ran on the ISS like every other).
    CHECK(shorter >= 5);
    CHECK(proven >= 150);
}

TEST_CASE("the constraint model's block is never longer, and its bound is the dependences' at least", "[unit][sched][block]") {
    const isa::Machine m = isa::load_machine("os-real");
    const std::vector<isa::Instr> ops = {instr(m, "fdiv f1, f2, f3"), instr(m, "fadd f4, f1, f1"), instr(m, "add r1, r2, r3")};
    const sched::BlockSchedule none = sched::block_schedule(m, ops, 0);
    CHECK(none.bundles == sched::list_schedule(m, ops)); // no budget: the list schedule as is
    const sched::BlockSchedule s = sched::block_schedule(m, ops, sched::kBlockSearchNodes);
    // fdiv, then fadd once it lands, then fadd's own landing: the chain is the length.
    const int chain = static_cast<int>(m.latency_of(ops[0].info()) + m.latency_of(ops[1].info()));
    CHECK(static_cast<int>(s.bundles.size()) == chain);
    CHECK(s.fewest == chain);
    CHECK(s.shortest());
}

TEST_CASE("expand_copies appends each copy with its words swapped, comments and virtuals as written", "[unit][sched][block]") {
    const std::string text = "#copy begin body\n"
                             "x_A:    fadd %v1, f30, f31   # f30 stays in a comment\n"
                             "        lw r10, IC_JUMPS_A(r10)\n"
                             "        jr r11\n"
                             "#copy end\n"
                             "done:\n"
                             "#copy body: f30-f31 = f50-f51, r10 = r11, *_A = *_B\n";
    // Markers blank, so "done:" keeps its line 6; the copy follows the last line.
    CHECK(sched::expand_copies(text, "t.pk") ==
          "\nx_A:    fadd %v1, f30, f31   # f30 stays in a comment\n        lw r10, IC_JUMPS_A(r10)\n        jr r11\n\n"
          "done:\n\n"
          "# ---- lines 2-4 copied by '#copy body' (line 7) ----\n"
          "x_B:    fadd %v1, f50, f51   # f30 stays in a comment\n        lw r11, IC_JUMPS_B(r11)\n        jr r10\n");
    CHECK(sched::expand_copies("        nop\n", "t.pk") == "        nop\n");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n        nop\n", "t.pk"),
                      "t.pk:1: error: '#copy begin' is never closed by '#copy end'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy b: r1 = r2\n#copy begin b\n#copy end\n", "t.pk"),
                      "t.pk:1: error: '#copy b' names no block closed before it ('#copy begin b' ... '#copy end')");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n#copy end\n#copy b: f1-f3 = f5-f6\n", "t.pk"),
                      "t.pk:3: error: '#copy': 3 registers against 2 in 'f1-f3 = f5-f6'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n#copy end\n#copy b: r1 r2\n", "t.pk"),
                      "t.pk:3: error: '#copy': each swap is 'X = Y' in 'r1 r2'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy end\n", "t.pk"), "t.pk:1: error: '#copy end' without '#copy begin'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin a\n#copy begin b\n", "t.pk"),
                      "t.pk:2: error: '#copy begin' inside another (they do not nest)");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n#copy b: r1 = r2\n#copy end\n", "t.pk"),
                      "t.pk:2: error: a '#copy' inside the block 'b' it would copy from (copy after '#copy end')");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n#copy end\n#copy b: f3-f1 = f5-f7\n", "t.pk"),
                      "t.pk:3: error: '#copy': a register range runs upwards (f30-f46) in 'f3-f1 = f5-f7'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy begin b\n#copy end\n#copy b: f1-f3 = f2-f4\n", "t.pk"),
                      "t.pk:3: error: '#copy': 'f2' or 'f3' is swapped twice in 'f1-f3 = f2-f4'");
    CHECK_THROWS_WITH(sched::expand_copies("#copy beginning\n", "t.pk"),
                      "t.pk:1: error: '#copy beginning' names no block closed before it ('#copy begin beginning' ... '#copy end')");
    // Expanding an expansion changes nothing (the kernel build expands before pack_source does).
    const std::string once = sched::expand_copies(text, "t.pk");
    CHECK(sched::expand_copies(once, "t.pk") == once);
    // pack_source schedules the copy like any other block.
    const isa::Machine m = isa::load_machine("os");
    const std::string pk = "#copy begin b\nl_A:\n#pack begin\n        li r1, 1\n        li r2, 2\n#pack end\n#copy end\n"
                           "        halt\n#copy b: r1 = r3, *_A = *_B\n";
    const sched::PackResult r = sched::pack_source(pk, "t.pk", m);
    REQUIRE(r.blocks.size() == 2);
    CHECK(r.blocks[0].line == 3); // the copy's block is reported at the line it copies
    CHECK(r.blocks[1].line == 3);
    CHECK(r.text.find("l_B:\n        { li r3, 1 ; li r2, 2 }") != std::string::npos);
}

TEST_CASE("an error in a #copy names the line it copies and the copy", "[unit][sched][block]") {
    const std::string pk = "#copy begin b\n#pack begin\n        li r1, 1\n#pack end\n#copy end\n        halt\n#copy b: r1 = q1\n";
    try {
        (void)sched::pack_source(pk, "t.pk", isa::load_machine("os"));
        FAIL("q1 is no register");
    } catch (const base::Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("t.pk:3:") != std::string::npos);
        CHECK(std::string(e.what()).find("[in the copy made by '#copy b' at line 7]") != std::string::npos);
        CHECK(std::string(e.what()).find("t.pk:10") == std::string::npos);
    }
}
