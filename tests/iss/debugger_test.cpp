// The debugger's command loop: Enter repeats a step; limits hold inside a step.
#include "helpers.hpp"

#include "iss/debugger.hpp"

#include <cstdio>
#include <chrono>
#include <thread>

using namespace nesshi;
using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {
// Everything the debugger printed to `f` so far.
std::string contents(std::FILE* f) {
    std::fflush(f);
    std::rewind(f);
    std::string out;
    for (int ch; (ch = std::fgetc(f)) != EOF;) out += char(ch);
    return out;
}
} // namespace

// `step`, a line of one space, an empty line: the blank line used to be stored as the step to
// repeat, and the empty line then indexed the empty word list of " " (a segmentation fault).
TEST_CASE("a blank line repeats the last step like an empty one") {
    auto p = make_proc("os", {{op("nop")}, {op("nop")}, {op("nop")}, {op("nop")}, {op("halt")}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    CHECK(d.execute("step"));
    CHECK(d.execute(" "));
    CHECK(d.execute(""));
    CHECK(d.execute("\t"));
    CHECK(p->cycle() == 4);
    CHECK(d.execute("step 1"));
    CHECK(d.execute(""));
    CHECK(p->status() == Status::Halted);
    // Nothing to repeat yet: a blank line does nothing.
    auto q = make_proc("os", {{op("halt")}});
    Debugger e(*q, out);
    CHECK(e.execute(" "));
    CHECK(q->cycle() == 0);
    std::fclose(out);
}

// A step of a bundle waiting on a word that may never come (an open channel holding one of the
// two words the bundle receives) stops at the debugger's cycle limit instead of never returning.
TEST_CASE("step stops at the debugger's cycle limit inside a wait") {
    auto p = make_proc("os", {{op("recv", 1, 0, 0, 0), op("recv", 2, 0, 0, 0)}, {op("halt")}});
    QueueChannel ch;
    ch.feed(7);
    p->attach_channel(0, &ch);
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    d.max_cycles = 50;
    CHECK(d.execute("step"));
    CHECK(p->cycle() == 50);
    CHECK(contents(out).find("stopped after 50 cycles (limit)") != std::string::npos);
    std::fclose(out);
}

// Ctrl-C during `continue`: the SIGINT handler sets Debugger::interrupt; the run stops before
// its next bundle with the state kept, the flag is cleared, and the session goes on.
TEST_CASE("setting the interrupt flag stops a continue and keeps the state") {
    // An endless loop: r2 stays 0.
    auto p = make_proc("os", {{op("li", 1, 0, 0, 0)}, {op("addi", 1, 1, 0, 1), op("beqz", 0, 2, 0, 1)}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    std::thread ctrl_c([&] { // as the signal handler would, from outside the run loop
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        d.interrupt.store(true);
    });
    CHECK(d.execute("continue"));
    ctrl_c.join();
    CHECK(p->status() == Status::Running);
    CHECK(p->cycle() > 0);
    CHECK(p->cycle() < d.max_cycles);
    CHECK(!d.interrupt.load());
    CHECK(contents(out).find("interrupted: cycle ") != std::string::npos);
    const uint64_t at = p->cycle();
    const uint32_t r1 = p->reg(R(1));
    CHECK(r1 == at - 1); // one addi per cycle after the li: nothing lost, nothing redone
    CHECK(d.execute("step"));
    CHECK(p->cycle() == at + 1);
    CHECK(p->reg(R(1)) == r1 + 1);
    // Set before a command starts, the flag stops it at once (debug_interactive clears it first).
    d.interrupt.store(true);
    CHECK(d.execute("step 5"));
    CHECK(p->cycle() == at + 1);
    std::fclose(out);
}

// `step -1` used to read -1 as 2^32 - 1 bundles and run to the end; `step 0` issued one.
TEST_CASE("step -1 is an error and step 0 does nothing") {
    auto p = make_proc("os", {{op("nop")}, {op("nop")}, {op("halt")}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    CHECK(d.execute("step -1"));
    CHECK(p->cycle() == 0);
    CHECK(contents(out).find("step takes a count of 0 or more, not -1") != std::string::npos);
    CHECK(d.execute("step 0"));
    CHECK(p->cycle() == 0);
    CHECK(d.execute("step 1"));
    CHECK(p->cycle() == 1);
    std::fclose(out);
}

TEST_CASE("run restarts with the breakpoints kept, the host refills its inputs") {
    auto p = make_proc("os", {{op("nop")}, {op("nop")}, {op("nop")}, {op("halt")}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    int restarts = 0;
    d.on_restart = [&] { ++restarts; };
    CHECK(d.execute("break 2"));
    CHECK(d.execute("continue"));
    CHECK(p->pc() == 2);
    CHECK(d.execute("continue"));
    CHECK(p->status() == Status::Halted);
    CHECK(d.execute("run"));
    CHECK(restarts == 1);
    CHECK(p->status() == Status::Running);
    CHECK(p->pc() == 2);
    CHECK(p->cycle() == 2);
    CHECK(d.execute("restart"));
    CHECK(restarts == 2);
    CHECK(p->cycle() == 0);
    CHECK(d.execute("break 0"));
    CHECK(d.execute("run")); // a breakpoint at pc 0 stops before anything issues
    CHECK(p->cycle() == 0);
    std::fclose(out);
}

TEST_CASE("TAB completion offers commands, info topics, registers and labels") {
    auto p = make_proc("os", {{op("nop")}, {op("nop")}, {op("halt")}}, Engine::Checked, {{"loop", 1}, {"done", 2}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    using V = std::vector<std::string>;
    CHECK(d.complete("con") == V{"continue"});
    CHECK(d.complete("re") == V{"restart"});
    CHECK(d.complete("info i") == V{"inflight"});
    CHECK(d.complete("break lo") == V{"loop"});
    CHECK(d.complete("print r12") == V{"r12", "r120", "r121", "r122", "r123", "r124", "r125", "r126", "r127"});
    CHECK(d.complete("p f127") == V{"f127"});
    CHECK(d.complete("until d") == V{"done"});
    CHECK(d.complete("x zz").empty());
    CHECK(d.complete("").size() == Debugger::commands().size());
    std::fclose(out);
}

TEST_CASE("the history file: XDG_STATE_HOME, else HOME, else none") {
    CHECK(debug_history_path("/s", "/h") == "/s/nesshi_history");
    CHECK(debug_history_path("", "/h") == "/h/.nesshi_history");
    CHECK(debug_history_path(nullptr, "/h") == "/h/.nesshi_history");
    CHECK(debug_history_path(nullptr, nullptr).empty());
    CHECK(debug_history_path(nullptr, "").empty());
}

// Arguments a command does not take are an error, never dropped: a condition on a breakpoint
// used to leave an unconditional one.
TEST_CASE("extra arguments are refused and nothing is done") {
    auto p = make_proc("os", {{op("nop")}, {op("nop")}, {op("halt")}});
    std::FILE* out = std::tmpfile();
    REQUIRE(out);
    Debugger d(*p, out);
    CHECK(d.execute("break 1 if r1 == 5"));
    CHECK(contents(out).find("break: unexpected 'if r1 == 5' (usage: break LOC); nothing done") != std::string::npos);
    CHECK(d.execute("continue"));
    CHECK(p->status() == Status::Halted); // no breakpoint was set
    CHECK(d.execute("stats now"));
    CHECK(contents(out).find("stats: unexpected 'now' (usage: stats); nothing done") != std::string::npos);
    CHECK(d.execute("info regs r extra"));
    CHECK(contents(out).find("info: unexpected 'extra'") != std::string::npos);
    CHECK(d.execute("x/2 0")); // the count and the address: two arguments
    CHECK(contents(out).find("x: unexpected") == std::string::npos);
    std::fclose(out);
}
