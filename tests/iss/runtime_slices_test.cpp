// A program whose runs may still be compiled at run time (iss/compiled.hpp: RuntimeCompile) runs a
// long Processor::run in slices and looks for its runs between two (Processor::dispatch). Here
// the mode waits for a cycle count never reached, so slicing is on for the whole run and nothing
// is compiled: every result must be the interpreter's.
#include "helpers.hpp"

#include "iss/compiled.hpp"

using namespace nesshi::iss;
using namespace nesshi::iss::test;

namespace {

constexpr uint64_t kSlice = uint64_t{1} << 20; // Processor::dispatch's

// Sets the mode for the programs loaded while it lives, and puts it back.
struct Mode {
    RuntimeCompile before = runtime_compile_mode();
    Mode(RuntimeCompile m, uint64_t after) { set_runtime_compile_mode(m, after); }
    ~Mode() { set_runtime_compile_mode(before); }
};

// A loop of `pad` + 2 bundles whose taken branch costs a 3-cycle bubble (which can carry a slice
// past its end, and past a limit just beyond it): counts in r1.
std::unique_ptr<Processor> loop(int pad) {
    nesshi::isa::Machine m = nesshi::isa::load_machine("os");
    m.name = "os-bubble-3";
    m.branch_penalty = 3;
    std::vector<Bundle> b(size_t(pad), Bundle{op("nop")});
    b.push_back({op("addi", 1, 1, 0, 1)});
    b.push_back({op("jmp", 0, 0, 0, uint32_t(pad))});
    return std::make_unique<Processor>(load_program(make_object(m, std::move(b)), m));
}

} // namespace

TEST_CASE("A cycle limit holds across the slices of a program that may still be compiled") {
    for (int pad = 0; pad < 5; ++pad)
        for (uint64_t limit = kSlice - 4; limit <= kSlice + 4; ++limit) {
            std::unique_ptr<Processor> plain;
            {
                Mode off(RuntimeCompile::Off, 0);
                plain = loop(pad);
            }
            Mode never(RuntimeCompile::Wait, ~uint64_t{0}); // for the whole run: never compiled
            std::unique_ptr<Processor> sliced = loop(pad);
            REQUIRE(plain->program().runtime_compiled() == nullptr);
            REQUIRE(sliced->program().runtime_compiled() != nullptr); // else nothing here is sliced
            INFO("pad " << pad << ", limit " << limit);
            const Status a = plain->run(limit), b = sliced->run(limit);
            CHECK(a == b);
            CHECK(plain->cycle() == sliced->cycle());
            CHECK(plain->reg(R(1)) == sliced->reg(R(1)));
            CHECK(sliced->cycle() < limit + 4); // a bubble may carry it past its limit, no further
        }
}

TEST_CASE("run_until on a blocked processor that may still be compiled waits to the cycle asked for") {
    Mode never(RuntimeCompile::Wait, ~uint64_t{0});
    QueueChannel open;
    auto c = make_proc("os", {{op("recv", 1, 0, 0, 0)}, {op("halt")}});
    REQUIRE(c->program().runtime_compiled() != nullptr);
    c->attach_channel(0, &open);
    CHECK(c->run_until(5 * kSlice) == Status::Blocked);
    CHECK(c->cycle() == 5 * kSlice);
    CHECK(c->counters().wait_cycles == 5 * kSlice);
}
