// The kernel build below the machine: a kernel scheduled for the machine at hand from its .pk
// source, the committed one on its preset, the same program when asked again, and none of the
// machine's compiled runs.
#include "kbuild/runner.hpp"

#include "isa/machine.hpp"
#include "iss/compiled.hpp"
#include "iss/processor.hpp"
#include "kernels/sources.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace nesshi;

// Where the machine tests' description files live (the build passes the folder).
static const std::string kData = NESSHI_TEST_DATA;

TEST_CASE("A variant's kernel is scheduled from its .pk source, the preset's is the committed one", "[unit][kbuild]") {
    const kernels::SourceSet src = kernels::embedded();
    const auto preset = kbuild::assemble_kernel(src, "ic/intersect.s", "ic");
    const auto variant = kbuild::assemble_kernel(src, "ic/intersect.s", kData + "/ic-2iu.toml");
    CHECK(preset->machine().name == "ic");
    CHECK(variant->machine().name == "ic-2iu");
    // The second IU shortens the straight-line bodies (the variant may take the hybrid kernel,
    // which has the bodies and the loops: its size says nothing).
    auto body = [](const iss::Program& p) { return p.find_symbol("tri2_A")->value - p.find_symbol("tri1_A")->value; };
    CHECK(body(*variant) < body(*preset));
    // The code around the voxel loop gets the nops os-real's latencies need, and the loop (a
    // .pipeline while region) is modulo-scheduled for it; the os preset runs the hand loop.
    kbuild::KernelBuild build;
    const auto real = kbuild::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &build);
    CHECK(real->machine().name == "os-real");
    CHECK(build.scheduled);
    CHECK(build.source == "kernels/os/dda.pk");
    CHECK(build.nops > 0);
    CHECK(real->find_symbol("__sa_kernel"));
    CHECK_FALSE(real->find_symbol("leave_b"));
    const auto os = kbuild::assemble_kernel(src, "os/dda.s", isa::load_machine("os"), &build);
    CHECK_FALSE(build.scheduled); // the committed kernel
    CHECK(build.source == "kernels/os/dda.s");
    CHECK(os->find_symbol("leave_b"));
    CHECK_FALSE(os->find_symbol("__sa_kernel"));
    CHECK_THROWS_WITH(kbuild::assemble_kernel(src, "os/dda.s", kData + "/os-32regs.toml"),
                      Catch::Contains("register r60 out of range: os-32regs has r0..r31"));
    // The IC kernel is straight-line bodies only (its pipeline across primitives is in the data
    // flow), so it is scheduled for realistic latencies as a whole.
    CHECK(kbuild::assemble_kernel(src, "ic/intersect.s", "ic-real")->machine().name == "ic-real");
}

TEST_CASE("A kernel scheduled once for a machine is the same program when asked again", "[unit][kbuild]") {
    const kernels::SourceSet src = kernels::embedded();
    kbuild::KernelBuild first, again;
    const auto a = kbuild::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &first);
    const auto b = kbuild::assemble_kernel(src, "os/dda.s", isa::load_machine("os-real"), &again); // the cached schedule
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
    CHECK_THROWS_WITH(kbuild::assemble_kernel(edited, "os/dda.s", isa::load_machine("os-real")),
                      Catch::Contains("nosuchop"));
}

TEST_CASE("The kernel build links none of the machine's compiled runs: its programs run threaded", "[unit][kbuild]") {
    // The build's generator of compiled runs links this library alone; the runs it writes register
    // themselves in the programs that link the machine (machine/CMakeLists.txt), never here.
    CHECK(iss::compiled_count() == 0);
    iss::set_runtime_compile_mode(iss::RuntimeCompile::Off); // not an object compiled at run time either
    kbuild::KernelRunner run(kbuild::assemble_kernel(kernels::embedded(), "os/dda.s", "os"));
    CHECK_FALSE(run.proc->compiled_runs());
}
