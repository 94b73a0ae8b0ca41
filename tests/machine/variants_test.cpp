// Machine variants: the stages on user descriptions. Models change timing, never results; a
// variant gets its kernels' straight-line blocks scheduled for it from the .pk sources.
#include "support.hpp"

#include "kernels/sources.hpp"
#include "machine/runner.hpp"
#include "rt/scene.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace nesshi;
using namespace nesshi::machine::test;

TEST_CASE("Variants render what the native renderer renders, a second IU speeds the IC up, latencies slow it", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 6);
    const rt::RenderOptions opt = small(16);
    const rt::RenderResult native = rt::render_native(prep, opt);
    const machine::Result base = machine::render(prep, opt, model(machine::Model::V));
    machine::Options mo = model(machine::Model::V);
    mo.os_machine = kData + "/os-3fpu.toml";
    mo.ic_machine = kData + "/ic-2iu.toml";
    const machine::Result var = machine::render(prep, opt, mo);
    CHECK(var.render.image.rgb == native.image.rgb);
    CHECK(var.render.stats.rays == native.stats.rays);
    CHECK(var.render.id_buffer == native.id_buffer);
    CHECK(var.render.t_buffer == native.t_buffer);
    CHECK(var.machine.ic.processing < base.machine.ic.processing);
    machine::Options real = model(machine::Model::V);
    real.ic_machine = "ic-real";
    const machine::Result slow = machine::render(prep, opt, real);
    CHECK(slow.render.id_buffer == native.id_buffer);
    CHECK(slow.render.image.rgb == native.image.rgb);
    // About twice the cycles (1.998x since straight blocks are shortened by the constraint model).
    CHECK(2 * slow.machine.ic.processing > 3 * base.machine.ic.processing);
}

TEST_CASE("The -real presets run the whole machine: results identical to native, every model slower", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 6);
    const rt::RenderOptions opt = small(16);
    const rt::RenderResult native = rt::render_native(prep, opt);
    for (machine::Model m : {machine::Model::S, machine::Model::M, machine::Model::V}) {
        INFO(machine::model_name(m));
        const machine::Result ideal = machine::render(prep, opt, model(m));
        machine::Options mo = model(m);
        mo.os_machine = "os-real";
        mo.ic_machine = "ic-real";
        mo.seq_machine = "seq-real";
        const machine::Result real = machine::render(prep, opt, mo);
        CHECK(real.render.image.rgb == native.image.rgb);
        CHECK(real.render.id_buffer == native.id_buffer);
        CHECK(real.render.stats.rays == native.stats.rays);
        CHECK(real.machine.total_cycles > ideal.machine.total_cycles);
    }
}

TEST_CASE("os-real's pipelined voxel loop renders native's image, ids and depths on an 8-voxel grid", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 8);
    const rt::RenderOptions opt = small(16);
    const rt::RenderResult native = rt::render_native(prep, opt);
    machine::Options mo = model(machine::Model::V);
    mo.os_machine = "os-real";
    const machine::Result real = machine::render(prep, opt, mo);
    CHECK(real.render.id_buffer == native.id_buffer);
    CHECK(real.render.image.rgb == native.image.rgb);
    CHECK(real.render.t_buffer == native.t_buffer);
    CHECK(real.render.stats.rays == native.stats.rays);
    // The build says how its loop was scheduled: the .pk's while loop, at its RecMII of 9 (lbu 2 +
    // bnez, the step's fle/and/sel/add chain) on os-real, with the line of its `.pipeline`.
    REQUIRE(real.machine.os_kernel.loops.size() == 1);
    const machine::KernelLoop& l = real.machine.os_kernel.loops[0];
    CHECK(l.is_while);
    CHECK(l.ii == l.mii);
    CHECK(l.stages >= 1);
    const std::string pk = kernels::embedded().text("os/dda.pk");
    std::size_t at = 0;
    for (int n = 1; n < l.line; ++n) at = pk.find('\n', at) + 1;
    CHECK(pk.compare(at, 24, "        .pipeline while\n") == 0);
    CHECK(real.machine.ic_kernel.loops.empty()); // the ic preset's committed kernel
}

// Three plausible slower OS machines whose kernel did not assemble ("f41 is read before its new
// value lands ... around a back edge"): the bundled blocks left a value in flight that hand code
// read, found only once the region was put back.
TEST_CASE("Slower OS variants render native's image: hazards the bundled blocks create are legalized", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 8);
    const rt::RenderOptions opt = small(16);
    const rt::RenderResult native = rt::render_native(prep, opt);
    for (const char* file : {"os-slow-fpu.toml", "os-real-nobubble.toml", "os-real-fpu4.toml"}) {
        INFO(file);
        machine::Options mo = model(machine::Model::V);
        mo.os_machine = kData + "/" + file;
        machine::Result r;
        REQUIRE_NOTHROW(r = machine::render(prep, opt, mo));
        CHECK(r.render.id_buffer == native.id_buffer);
        CHECK(r.render.image.rgb == native.image.rgb);
        CHECK(r.render.t_buffer == native.t_buffer);
    }
}

// Monotone in resources (issue 25): an OS with a third FPU and write port and the same latencies
// was 5-12 % busier than its preset, its hand voxel loop replaced by the generated one. The
// committed kernel is now a candidate measured against the generated one. The same for the IC
// with a second IU: on ic the committed kernel is one candidate, on ic-real both sources are
// scheduled for each machine.
TEST_CASE("A stage with more resources and the same latencies is never busier than its preset", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 8);
    const rt::RenderOptions opt = small(24);
    struct Pair {
        bool os;
        const char *preset, *bigger;
    };
    for (const Pair& p : {Pair{true, "os", "os-3fpu.toml"}, Pair{true, "os-real", "os-real-3fpu.toml"},
                          Pair{false, "ic", "ic-2iu.toml"}, Pair{false, "ic-real", "ic-real-2iu.toml"}}) {
        INFO(p.preset);
        machine::Options base = model(machine::Model::V), big = base;
        (p.os ? base.os_machine : base.ic_machine) = p.preset;
        (p.os ? big.os_machine : big.ic_machine) = kData + "/" + p.bigger;
        const machine::Result a = machine::render(prep, opt, base), b = machine::render(prep, opt, big);
        const auto busy = [&](const machine::Result& r) {
            const auto& st = p.os ? r.machine.os : r.machine.ic;
            return double(st.processing + st.communication);
        };
        CHECK(busy(b) <= busy(a) * 1.005);
        CHECK(b.render.id_buffer == a.render.id_buffer);
        // The preset's kernel is a candidate on its superset (os's committed one, os-real's as
        // scheduled for os-real), and the render says which candidate ran and what the others cost.
        const machine::KernelBuild& kb = p.os ? b.machine.os_kernel : b.machine.ic_kernel;
        CHECK_FALSE(kb.choice.empty());
        if (std::string(p.preset).ends_with("-real")) CHECK(kb.choice.find(std::string("scheduled for ") + p.preset) != std::string::npos);
    }
}

TEST_CASE("A variant's kernel is scheduled from its .pk source, the preset's is the committed one", "[unit][machine]") {
    const kernels::SourceSet src = kernels::embedded();
    const auto preset = machine::assemble_kernel(src, "ic/intersect.s", "ic");
    const auto variant = machine::assemble_kernel(src, "ic/intersect.s", kData + "/ic-2iu.toml");
    CHECK(preset->machine().name == "ic");
    CHECK(variant->machine().name == "ic-2iu");
    // The second IU shortens the straight-line bodies (the variant may take the hybrid kernel,
    // which has the bodies and the loops: its size says nothing).
    auto body = [](const iss::Program& p) { return p.find_symbol("tri2_A")->value - p.find_symbol("tri1_A")->value; };
    CHECK(body(*variant) < body(*preset));
    // The code around the voxel loop gets the nops os-real's latencies need, and the loop (a
    // .pipeline while region) is modulo-scheduled for it; the os preset runs the hand loop.
    machine::KernelBuild build;
    const auto real = machine::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &build);
    CHECK(real->machine().name == "os-real");
    CHECK(build.scheduled);
    CHECK(build.source == "kernels/os/dda.pk");
    CHECK(build.nops > 0);
    CHECK(real->find_symbol("__sa_kernel"));
    CHECK_FALSE(real->find_symbol("leave_b"));
    const auto os = machine::assemble_kernel(src, "os/dda.s", isa::load_machine("os"), &build);
    CHECK_FALSE(build.scheduled); // the committed kernel
    CHECK(build.source == "kernels/os/dda.s");
    CHECK(os->find_symbol("leave_b"));
    CHECK_FALSE(os->find_symbol("__sa_kernel"));
    CHECK_THROWS_WITH(machine::assemble_kernel(src, "os/dda.s", kData + "/os-32regs.toml"),
                      Catch::Contains("register r60 out of range: os-32regs has r0..r31"));
    // The IC kernel is straight-line bodies only (its pipeline across primitives is in the data
    // flow), so it is scheduled for realistic latencies as a whole.
    CHECK(machine::assemble_kernel(src, "ic/intersect.s", "ic-real")->machine().name == "ic-real");
}

TEST_CASE("A kernel scheduled once for a machine is the same program when asked again", "[unit][machine]") {
    const kernels::SourceSet src = kernels::embedded();
    machine::KernelBuild first, again;
    const auto a = machine::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &first);
    const auto b = machine::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &again); // the cached schedule
    CHECK(again.scheduled);
    CHECK(again.source == first.source);
    CHECK(again.blocks == first.blocks);
    CHECK(again.blocks_shortest == first.blocks_shortest);
    CHECK(first.blocks_shortest > 0); // the constraint model proves most blocks shortest
    CHECK(first.blocks_shortest <= first.blocks);
    CHECK(again.nops == first.nops);
    REQUIRE(a->size() == b->size());
    for (std::size_t i = 0; i < a->size(); ++i) CHECK(a->format_bundle(i) == b->format_bundle(i));
    // Another source set (one file changed, here broken) is scheduled afresh, not served from the cache.
    kernels::SourceSet edited = src;
    for (kernels::SourceFile& f : edited.files)
        if (f.path == "os/dda.pk") f.text += "\n    nosuchop r1, r2, r3\n";
    CHECK_THROWS_WITH(machine::assemble_kernel(edited, "os/dda.s", isa::load_machine("os-real")),
                      Catch::Contains("nosuchop"));
}
