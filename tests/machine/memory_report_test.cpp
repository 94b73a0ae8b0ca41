// The memory report (machine/memory_report.hpp) against the machine: "fits" exactly when the
// machine takes a grid, "fits resident" exactly when it puts every IC datum in resident memory.
#include "support.hpp"

#include "machine/machine.hpp"
#include "machine/memory_report.hpp"
#include "rt/render.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

using namespace nesshi;
using namespace nesshi::rt;

using machine::test::model;
using machine::test::small;

TEST_CASE("The memory report of a 100^3 grid: its map fits the OS SRAM, its IC data exceed resident memory", "[unit][machine]") {
    Scene sc = parse_nff("f 1 1 1 1 0 0 0 1\ns 0 0 0 1\ns 3 3 3 1\n", "two.nff");
    ShapeSet set = build_shapes(sc);
    Grid g = build_grid(sc, set, 100);
    const machine::MemoryReport m = machine::memory_report(g, set.shapes.size());
    CHECK(m.os_voxel_map == 1000000);
    CHECK(m.os_padded_map == 102 * 102 * 102); // the machine's map has a one-voxel frame
    CHECK(m.os_total() == 0x90000 + 102 * 102 * 102);
    CHECK(m.os_fits());
    CHECK(m.ic_offsets == 4 * 102 * 102 * 102);                  // a list address per padded voxel
    CHECK(m.ic_shapes == 3 * 80);                                // END record + 2 records
    CHECK(m.ic_lists == 4 * (g.prims.size() + 102 * 102 * 102 + 1)); // + an END word per list, read-ahead
    CHECK(m.ic_total() == 256 + m.ic_offsets + m.ic_lists + m.ic_shapes);
    CHECK_FALSE(m.ic_resident_fits());
    CHECK(m.os_sram_bytes == 2u << 20);
    CHECK(m.text().find("0.000 MiB") == std::string::npos);
}

TEST_CASE("The memory report says the voxel map fits the OS SRAM exactly when the machine takes it", "[unit][machine]") {
    // The padded map sits at 0x90000: 112^3 is the largest grid that fits (an unpadded count
    // against 2 MiB said 128^3). 113..128 are the grids where report and machine used to disagree.
    for (int n : {112, 113, 120, 128}) {
        INFO("tetra:1 grid " << n);
        const PreparedScene prep = prepare(load_scene("tetra:1"), n);
        const machine::MemoryReport m = machine::memory_report(prep.grid, prep.shapes.shapes.size());
        CHECK(m.os_fits() == (n <= 112));
        CHECK(m.os_padded_map == static_cast<std::size_t>(n + 2) * (n + 2) * (n + 2));
        CHECK(m.os_total() == 0x90000 + m.os_padded_map);
        bool machine_takes_it = true;
        try {
            machine::render(prep, small(1), model(machine::Model::V));
        } catch (const std::runtime_error& e) {
            CHECK_THAT(e.what(), Catch::Contains("does not fit the OS SRAM"));
            machine_takes_it = false;
        }
        CHECK(machine_takes_it == m.os_fits());
        const nlohmann::json j = machine::with_memory_report(stats_json(prep, small(1), render_native(prep, small(1)), "native"),
                                                             prep.grid, prep.shapes.shapes.size());
        CHECK(j["grid"]["memory"]["os_fits"].get<bool>() == m.os_fits());
        CHECK(j["grid"]["memory"]["os_total_bytes"].get<std::size_t>() == m.os_total());
    }
}

TEST_CASE("The memory report says the IC data fit resident memory exactly when the machine puts them there", "[unit][machine]") {
    // tetra:1: the padded voxel table and the lists' END words fill 1 MiB from grid 48; the
    // report used to count the unpadded table without END words (grid 50: "0.535 MiB, fits resident").
    for (int n : {20, 47, 48, 50}) {
        INFO("tetra:1 grid " << n);
        const PreparedScene prep = prepare(load_scene("tetra:1"), n);
        const machine::MemoryReport m = machine::memory_report(prep.grid, prep.shapes.shapes.size());
        CHECK(m.ic_resident_fits() == (n <= 47));
        CHECK(m.ic_resident_fits() == (m.ic_total() <= m.ic_resident_bytes));
        CHECK(m.ic_resident_bytes == 1u << 20);
        machine::Options mo = model(machine::Model::V);
        mo.cache.enabled = true; // counts the accesses to global memory
        const machine::Result r = machine::render(prep, small(4), mo);
        CHECK((r.machine.cache_accesses == 0) == m.ic_resident_fits());
    }
}


// The report used to describe the default machine whatever the options: a 1 MiB cache under
// --cache-size 65536, and "fits resident" under --no-resident.
TEST_CASE("The memory report follows --cache-size and --no-resident", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("tetra:1"), 10);
    const std::size_t shapes = prep.shapes.shapes.size();
    machine::Options mo = model(machine::Model::V);
    const machine::MemoryReport ideal = machine::memory_report(prep.grid, shapes, mo);
    CHECK(ideal.text() == machine::memory_report(prep.grid, shapes).text()); // the default machine: as before
    CHECK(ideal.json() == machine::memory_report(prep.grid, shapes).json());
    mo.cache.enabled = true;
    mo.cache.bytes = 65536;
    mo.resident = false;
    const machine::MemoryReport m = machine::memory_report(prep.grid, shapes, mo);
    CHECK(m.ic_cache_bytes == 65536);
    CHECK(m.ic_no_resident);
    CHECK_THAT(m.text(), Catch::Contains("+ 0.062 MiB LRU cache (--no-resident: all in global memory, behind the cache)"));
    const nlohmann::json j = nlohmann::json::parse(m.json());
    CHECK(j["ic_cache_bytes"].get<std::size_t>() == 65536);
    CHECK(j["ic_no_resident"].get<bool>());
    // The machine's stats JSON carries the same report; with --no-resident every IC access goes to global memory.
    const RenderOptions opt = small(4);
    const machine::Result r = machine::render(prep, opt, mo);
    const nlohmann::json s = machine::stats_json(prep, opt, mo, r);
    CHECK(s["grid"]["memory"] == j);
    CHECK(r.machine.cache_accesses > 0);
}
