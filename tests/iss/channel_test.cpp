// FIFO word files, [CH=]FILE specs and the sparse channel table.
#include "helpers.hpp"

#include "iss/channel.hpp"

#include <stdexcept>

using namespace nesshi;
using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {
std::string word_error(std::string_view text) {
    try {
        parse_words(text, "w.txt");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "no error";
}

std::string spec_error(std::string_view spec) {
    try {
        parse_channel_spec(spec, 0);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}
} // namespace

TEST_CASE("word files: integers, hex and floats, one sign at most") {
    CHECK(parse_words("1 -1 +2 0x10 -0x1 # comment\n4294967295 -2147483648 1.0 -inf\n", "w.txt") ==
          std::vector<uint32_t>{1, 0xffffffffu, 2, 16, 0xffffffffu, 0xffffffffu, 0x80000000u, 0x3f800000u,
                                0xff800000u});
    // A second sign used to be accepted once the first was stripped; "--9223372036854775808" then
    // overflowed the negation (undefined behaviour).
    CHECK(word_error("--9223372036854775808") == "w.txt:1:1: error: bad word '--9223372036854775808'");
    CHECK(word_error("--5") == "w.txt:1:1: error: bad word '--5'");
    CHECK(word_error("1 +-5") == "w.txt:1:3: error: bad word '+-5'");
    CHECK(word_error("-+5") == "w.txt:1:1: error: bad word '-+5'");
    CHECK(word_error("--0x5") == "w.txt:1:1: error: bad word '--0x5'");
    CHECK(word_error("--1.5") == "w.txt:1:1: error: bad word '--1.5'");
    CHECK(word_error("-") == "w.txt:1:1: error: bad word '-'");
    CHECK(word_error("4294967296") == "w.txt:1:1: error: bad word '4294967296'");
    CHECK(word_error("-2147483649") == "w.txt:1:1: error: bad word '-2147483649'");
    CHECK(word_error("99999999999999999999999") == "w.txt:1:1: error: bad word '99999999999999999999999'");
}

TEST_CASE("channel specs CH=FILE: the channel is a number 0..4294967295, checked strictly") {
    CHECK(parse_channel_spec("in.txt", 0) == std::pair<uint32_t, std::string>{0, "in.txt"});
    CHECK(parse_channel_spec("out.txt", 1) == std::pair<uint32_t, std::string>{1, "out.txt"});
    CHECK(parse_channel_spec("3=in.txt", 0) == std::pair<uint32_t, std::string>{3, "in.txt"});
    CHECK(parse_channel_spec("4294967295=o=x", 0) == std::pair<uint32_t, std::string>{4294967295u, "o=x"});
    CHECK(parse_channel_spec("dir/a=b.txt", 0) == std::pair<uint32_t, std::string>{0, "dir/a=b.txt"});
    // Used to be stoul's bare "stoul", and a silent channel 0 for 2^32.
    CHECK(spec_error("99999999999999999999=o.txt") ==
          "channel 99999999999999999999 in '99999999999999999999=o.txt' is out of range (0..4294967295)");
    CHECK(spec_error("4294967296=o.txt") == "channel 4294967296 in '4294967296=o.txt' is out of range (0..4294967295)");
    CHECK(spec_error("12a=o.txt") == "bad channel '12a' in '12a=o.txt' (expected [CH=]FILE, CH a number 0..4294967295)");
    CHECK(spec_error("5=") == "no file after '=' in '5='");
}

// The channel table used to be a dense vector indexed by id: attaching channel 500000000 asked
// for 4 GB, 4294967295 for 32 GB.
TEST_CASE("channel ids are sparse: any 32-bit id costs one slot") {
    auto p = make_proc("os", {{op("recv", 1, 0, 0, 500000000)}, {op("send", 0, 1, 0, 4294967295u)}, {op("halt")}});
    CHECK(p->program().channel_ids() == std::vector<uint32_t>{500000000, 4294967295u});
    QueueChannel in, out, unused;
    in.feed(42);
    p->attach_channel(500000000, &in);
    p->attach_channel(4294967295u, &out);
    p->attach_channel(7, &unused); // a channel the program does not use is kept, and harmless
    CHECK(p->channel(500000000) == &in);
    CHECK(p->channel(4294967295u) == &out);
    CHECK(p->channel(7) == &unused);
    CHECK(p->channel(8) == nullptr);
    REQUIRE(p->run(100) == Status::Halted);
    CHECK(out.drain_all() == std::vector<uint32_t>{42});
    // Attachments survive a reset, and a channel can be replaced or detached.
    p->reset();
    QueueChannel in2;
    in2.feed(5);
    p->attach_channel(500000000, &in2);
    REQUIRE(p->run(100) == Status::Halted);
    CHECK(out.drain_all() == std::vector<uint32_t>{5});
    p->reset();
    p->attach_channel(500000000, nullptr);
    REQUIRE(p->run(100) == Status::Faulted);
    CHECK(p->fault()->message == "recv uses channel 500000000, which is not attached");
}
