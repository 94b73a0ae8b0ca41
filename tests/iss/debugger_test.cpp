// The debugger's command loop: Enter repeats a step; limits hold inside a step.
#include "helpers.hpp"

#include "iss/debugger.hpp"

#include <cstdio>

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
