// The scene sample a render measures its IC kernel's candidates on (kbuild/scene_sample.hpp),
// and the choice it makes with it.
#include "support.hpp"

#include "kbuild/runner.hpp"
#include "kbuild/scene_sample.hpp"
#include "rt/scene.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using namespace nesshi;
using namespace nesshi::machine::test;

namespace {

std::uint64_t nonempty_visits(const rt::RenderStats& s) {
    std::uint64_t n = 0;
    for (const rt::TraceCounters& c : s.traversal) n += c.nonempty_voxels;
    return n;
}
} // namespace

TEST_CASE("A scene sample is the native renderer's visits of the sampled corners", "[unit][machine]") {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 8);
    const rt::RenderOptions opt = small(16); // 17 x 17 corners: the default raster takes them all
    const kbuild::SceneSample s = kbuild::sample_scene(prep, opt);
    CHECK(s.corners == 17u * 17u);
    CHECK(s.visits.size() == nonempty_visits(rt::render_native(prep, opt).stats));
    REQUIRE(!s.visits.empty());
    for (const auto& v : s.visits) REQUIRE(v.voxel < s.lists.size());
    for (const auto& l : s.lists) {
        REQUIRE(!l.empty());
        for (std::uint32_t i : l) REQUIRE(i < s.shapes.size());
    }
    CHECK(s.shapes.size() <= prep.shapes.shapes.size());
    const kbuild::SceneSample again = kbuild::sample_scene(prep, opt);
    REQUIRE(again.visits.size() == s.visits.size());
    for (std::size_t i = 0; i < s.visits.size(); ++i) CHECK(again.visits[i].words() == s.visits[i].words());
    // A coarser raster of a bigger image: fewer corners, fewer visits.
    const kbuild::SceneSample coarse = kbuild::sample_scene(prep, small(64), 9);
    CHECK(coarse.corners == 81u);
    CHECK(coarse.visits.size() < nonempty_visits(rt::render_native(prep, small(64)).stats));
}

TEST_CASE("The IC kernel is chosen on the scene: padded pipeline on short lists, per-kind loops on long ones",
          "[unit][machine]") {
    machine::Options mo = model(machine::Model::V);
    mo.ic_machine = kData + "/ic-div-5.toml";
    const rt::RenderOptions opt = small(24);
    auto run = [&](int grid, const std::string& kernels_dir) {
        const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:2"), grid);
        machine::Options o = mo;
        o.kernels_dir = kernels_dir;
        const machine::Result r = machine::render(prep, opt, o);
        CHECK(r.render.id_buffer == rt::render_native(prep, opt).id_buffer);
        return r;
    };
    const machine::Result fine = run(40, ""); // 1.35 shapes per non-empty voxel
    CHECK(fine.machine.ic_kernel.source == "kernels/ic/intersect.pk");
    CHECK(fine.machine.ic_kernel.candidates == 5); // the bodies, the loops, the hybrid of both for lists of 4, 8, 16 or more
    CHECK(fine.machine.ic_kernel.choice.find("on this scene's sample") != std::string::npos);
    const machine::Result coarse = run(2, ""); // 18.75
    CHECK(coarse.machine.ic_kernel.source == "kernels/ic/intersect.loops.pk");
    // The sample predicts the whole run: without the loops the coarse grid's IC is busier.
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "nesshi-scene-sample-test";
    std::filesystem::remove_all(dir);
    std::filesystem::copy(NESSHI_KERNELS_DIR, dir, std::filesystem::copy_options::recursive);
    std::filesystem::remove(dir / "ic" / "intersect.loops.pk");
    const machine::Result without = run(2, dir.string());
    CHECK(without.machine.ic_kernel.source == "kernels/ic/intersect.pk");
    CHECK(without.machine.ic.load() > coarse.machine.ic.load());
    std::filesystem::remove_all(dir);
}

// The hybrid joins two kernels scheduled apart: a loops start that would change a register the
// dispatch kernel set up once (here the voxel table's address) is refused, and the render says why;
// so is one written as a hand bundle with its slot named.
TEST_CASE("A hybrid whose parts would clobber each other's set-up is refused, with the reason", "[unit][machine]") {
    const std::string once = "hybrid_start:\n#pack begin\n", entry = "#pack end\nfrom_dispatch:\n";
    for (const auto& [at, insert] : {std::pair{once, std::string("        li r20, 0\n")},
                                     std::pair{entry, std::string("        { iu0: li r20, 0 }\n")}}) {
        INFO(insert);
        const std::filesystem::path dir = std::filesystem::temp_directory_path() / "nesshi-hybrid-refused-test";
        std::filesystem::remove_all(dir);
        std::filesystem::copy(NESSHI_KERNELS_DIR, dir, std::filesystem::copy_options::recursive);
        const std::filesystem::path loops = dir / "ic" / "intersect.loops.pk";
        std::ifstream in(loops);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        REQUIRE(text.find(at) != std::string::npos);
        // after the block's opening, or before the entry label
        if (at == once) text.replace(text.find(at), at.size(), at + insert);
        else text.replace(text.find(at), at.size(), "#pack end\n" + insert + "from_dispatch:\n");
        std::ofstream(loops) << text;
        machine::Options mo = model(machine::Model::V);
        mo.ic_machine = kData + "/ic-div-5.toml";
        mo.kernels_dir = dir.string();
        const rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 8);
        const machine::Result r = machine::render(prep, small(16), mo);
        CHECK(r.render.id_buffer == rt::render_native(prep, small(16)).id_buffer);
        CHECK(r.machine.ic_kernel.candidates == 2); // the bodies and the loops; no hybrid
        CHECK_THAT(r.machine.ic_kernel.choice, Catch::Contains("the loops' start sets r20 to another value than the dispatch kernel's"));
        std::filesystem::remove_all(dir);
    }
}
