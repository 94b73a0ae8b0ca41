// The macropipeline host: models S, M, V against the native renderer, the cycle accounting,
// determinism, FIFO capacity and deadlock, the cache, capacity errors, the stats golden file.
#include "support.hpp"

#include "machine/machine.hpp"
#include "machine/provenance.hpp"
#include "rt/scene.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

using namespace nesshi;
using namespace nesshi::rt;

using machine::test::model;
using machine::test::small;

namespace {

void require_same_result(const RenderResult& a, const RenderResult& b) {
    REQUIRE(a.image.rgb == b.image.rgb);
    REQUIRE(a.id_buffer == b.id_buffer);
    REQUIRE(a.t_buffer == b.t_buffer);
    REQUIRE(a.stats.rays == b.stats.rays);
}

// Each processor's clock runs to its PE's end: processing + communication + wait = elapsed, for
// every PE's OS, IC and SC on its own (a sum over PEs could hide errors that cancel), and the
// machine's per-stage figures are the sums of the PEs'.
void require_accounting(const machine::Stats& m) {
    REQUIRE(m.pe_cycles.size() >= 1);
    REQUIRE(m.per_pe.size() == m.pe_cycles.size());
    machine::StageCycles os, ic, sc;
    for (std::size_t p = 0; p < m.per_pe.size(); ++p) {
        INFO("PE " << p << " of " << m.per_pe.size());
        const machine::PeCycles& pe = m.per_pe[p];
        CHECK(pe.end == m.pe_cycles[p]);
        CHECK(pe.os.processing + pe.os.communication + pe.os.wait == pe.end);
        CHECK(pe.ic.processing + pe.ic.communication + pe.ic.wait == pe.end);
        CHECK(pe.sc.processing + pe.sc.communication + pe.sc.wait == pe.end);
        CHECK(pe.os.processing > 0);
        CHECK(pe.ic.processing > 0);
        CHECK(pe.sc.processing > 0);
        os += pe.os;
        ic += pe.ic;
        sc += pe.sc;
    }
    for (auto [sum, total] : {std::pair{&os, &m.os}, std::pair{&ic, &m.ic}, std::pair{&sc, &m.sc}}) {
        CHECK(sum->processing == total->processing);
        CHECK(sum->communication == total->communication);
        CHECK(sum->wait == total->wait);
    }
    CHECK(m.total_cycles == *std::max_element(m.pe_cycles.begin(), m.pe_cycles.end()));
}

std::string fmt_slots(std::size_t cap) {
    const int n = machine::deadlock_free_ray_slots(cap);
    return "no FIFO can fill: limit them with --ray-slots " + std::to_string(n);
}

} // namespace

TEST_CASE("Models S, M and V render exactly what the native renderer renders", "[unit][machine]") {
    for (const char* name : {"tetra:1", "balls:1", "mount:1", "rings:1", "tree:1"}) {
        const PreparedScene prep = prepare(load_scene(name), 6);
        const RenderOptions opt = small(12);
        const RenderResult native = render_native(prep, opt);
        for (machine::Model m : {machine::Model::V, machine::Model::M, machine::Model::S}) {
            INFO(name << " model " << machine::model_name(m));
            const machine::Result r = machine::render(prep, opt, model(m));
            require_same_result(native, r.render);
            require_accounting(r.machine);
            CHECK(r.machine.hits + r.machine.returns == r.machine.visits);
        }
    }
}

TEST_CASE("Model S equals the sum of model M's stage loads (derived S is exact)", "[unit][machine]") {
    for (const char* name : {"mount:1", "rings:1"}) {
        const PreparedScene prep = prepare(load_scene(name), 5);
        const RenderOptions opt = small(10);
        const machine::Result m = machine::render(prep, opt, model(machine::Model::M));
        const machine::Result s = machine::render(prep, opt, model(machine::Model::S));
        INFO(name);
        CHECK(m.machine.s_cycles == m.machine.os.load() + m.machine.ic.load() + m.machine.sc.load());
        CHECK(s.machine.total_cycles == m.machine.s_cycles);
        // the same instruction streams: the same bundles and operations per stage
        CHECK(s.machine.os.bundles == m.machine.os.bundles);
        CHECK(s.machine.ic.ops == m.machine.ic.ops);
        CHECK(s.machine.sc.processing == m.machine.sc.processing);
        // a pipeline is never slower than one processor doing everything
        CHECK(m.machine.total_cycles < s.machine.total_cycles);
    }
}

TEST_CASE("The same cycles for any host thread count, PEs split the work", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("balls:1"), 6);
    const RenderOptions opt = small(12);
    const RenderResult native = render_native(prep, opt);
    machine::Options mo = model(machine::Model::V);
    mo.pes = 3;
    const machine::Result one = machine::render(prep, opt, mo);
    mo.threads = 3;
    const machine::Result three = machine::render(prep, opt, mo);
    require_same_result(native, one.render);
    require_same_result(native, three.render);
    CHECK(one.machine.pe_cycles == three.machine.pe_cycles);
    CHECK(one.machine.os.wait == three.machine.os.wait);
    CHECK(one.machine.ic.processing == three.machine.ic.processing);
    require_accounting(one.machine);
    const machine::Result single = machine::render(prep, opt, model(machine::Model::V));
    CHECK(one.machine.total_cycles < single.machine.total_cycles);
}

TEST_CASE("Cycle accounting adds up for each PE's OS, IC and SC, every model, 2 and 3 PEs", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("mount:1"), 6);
    const RenderOptions opt = small(12);
    for (machine::Model m : {machine::Model::V, machine::Model::M, machine::Model::S})
        for (int pes : {2, 3})
            for (bool dynamic : {false, true}) {
                INFO("model " << machine::model_name(m) << ", " << pes << " PEs" << (dynamic ? ", dynamic" : ""));
                machine::Options mo = model(m);
                mo.pes = pes;
                mo.dynamic_balance = dynamic;
                mo.epoch = 2000;
                const machine::Result r = machine::render(prep, opt, mo);
                REQUIRE(r.machine.per_pe.size() == static_cast<std::size_t>(pes));
                require_accounting(r.machine);
            }
}

TEST_CASE("Dynamic balancing: same results, deterministic, PEs finish together", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("mount:1"), 10);
    const RenderOptions opt = small(48);
    const RenderResult native = render_native(prep, opt);
    machine::Options inter = model(machine::Model::V);
    inter.pes = 3;
    machine::Options dyn = inter;
    dyn.dynamic_balance = true;
    const machine::Result i = machine::render(prep, opt, inter);
    const machine::Result d1 = machine::render(prep, opt, dyn);
    dyn.threads = 3;
    const machine::Result d3 = machine::render(prep, opt, dyn);
    require_same_result(native, d1.render);
    require_same_result(native, d3.render);
    require_accounting(d1.machine);
    CHECK(d1.machine.pe_cycles == d3.machine.pe_cycles);
    CHECK(d1.machine.ic.processing == d3.machine.ic.processing);
    auto spread = [](const std::vector<std::uint64_t>& v) {
        return *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end());
    };
    // Interleaving leaves this PE set ~2% apart; DIS handing out corners by demand, one epoch.
    CHECK(spread(d1.machine.pe_cycles) < spread(i.machine.pe_cycles));
    CHECK(spread(d1.machine.pe_cycles) <= dyn.epoch);
    // Models S and M under dynamic balancing, and one PE (topped up every epoch, never starved).
    for (machine::Model m : {machine::Model::S, machine::Model::M}) {
        machine::Options o = model(m);
        o.pes = 2;
        o.dynamic_balance = true;
        require_same_result(native, machine::render(prep, opt, o).render);
    }
    machine::Options one = model(machine::Model::V);
    const machine::Result single = machine::render(prep, opt, one);
    one.dynamic_balance = true;
    const machine::Result single_dyn = machine::render(prep, opt, one);
    CHECK(static_cast<double>(single_dyn.machine.total_cycles) <
          1.02 * static_cast<double>(single.machine.total_cycles));
}

TEST_CASE("Bounded FIFOs, FIFO latency and a real cache change timing, never results", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("mount:1"), 6);
    const RenderOptions opt = small(12);
    const machine::Result ideal = machine::render(prep, opt, model(machine::Model::V));
    machine::Options bounded = model(machine::Model::V);
    bounded.fifo_capacity = 64;
    bounded.window = 2;
    const machine::Result b = machine::render(prep, opt, bounded);
    require_same_result(ideal.render, b.render);
    CHECK(b.machine.max_fifo_words <= 64);
    CHECK(ideal.machine.max_fifo_words > 64);
    // One corner in flight: every FIFO hop is on the critical path, so latency adds up.
    machine::Options serial = model(machine::Model::V);
    serial.window = 1;
    const machine::Result s1 = machine::render(prep, opt, serial);
    machine::Options slow = serial;
    slow.fifo_latency = 10;
    const machine::Result l = machine::render(prep, opt, slow);
    require_same_result(ideal.render, l.render);
    CHECK(l.machine.total_cycles > s1.machine.total_cycles + 10 * (l.machine.visits + l.machine.hits));
    CHECK(s1.machine.total_cycles > ideal.machine.total_cycles);
    require_accounting(l.machine);
    machine::Options cached = model(machine::Model::V);
    cached.cache.enabled = true;
    cached.resident = false; // everything behind the cache
    cached.cache.bytes = 1024; // tiny, so that it misses
    cached.cache.ways = 2;
    const machine::Result c = machine::render(prep, opt, cached);
    require_same_result(ideal.render, c.render);
    CHECK(c.machine.cache_misses > 0);
    CHECK(c.machine.total_cycles > ideal.machine.total_cycles);
}

TEST_CASE("IC data larger than resident memory: the most-referenced records stay resident", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("tetra:1"), 64); // voxel table: 66^3 words > 1 MiB
    const RenderOptions opt = small(8);
    const RenderResult native = render_native(prep, opt);
    machine::Options hot = model(machine::Model::V);
    hot.cache.enabled = true;
    machine::Options global = hot;
    global.resident = false;
    const machine::Result h = machine::render(prep, opt, hot);
    const machine::Result g = machine::render(prep, opt, global);
    require_same_result(native, h.render);
    require_same_result(native, g.render);
    CHECK(h.machine.cache_accesses > 0);                       // table and lists: global memory
    CHECK(h.machine.cache_accesses < g.machine.cache_accesses); // records: resident
    CHECK(h.machine.cache_misses < g.machine.cache_misses);
}

TEST_CASE("A FIFO cycle filled to capacity is reported as a deadlock", "[unit][machine]") {
    // mount: a hit spawns a shadow, a reflection and a refraction ray (27 words) into the OS's
    // FIFO, which IC returns and eye rays keep full, while the OS waits to send to a full SC FIFO.
    const PreparedScene prep = prepare(load_scene("mount:1"), 6);
    machine::Options mo = model(machine::Model::V);
    mo.fifo_capacity = 16;
    try {
        machine::render(prep, small(24), mo);
        FAIL("no deadlock");
    } catch (const std::runtime_error& e) {
        const std::string msg = e.what();
        CHECK(msg.find("deadlock") != std::string::npos);
        CHECK(msg.find("full output") != std::string::npos);
    }
}

TEST_CASE("Rays in flight limited to capacity / 12: small FIFOs never fill, never deadlock", "[unit][machine]") {
    CHECK(machine::deadlock_free_ray_slots(0) == 0);
    CHECK(machine::deadlock_free_ray_slots(16) == 1);
    CHECK(machine::deadlock_free_ray_slots(64) == 5);
    CHECK(machine::deadlock_free_ray_slots(1024) == 85);
    // The audit's case: balls at the default window of 64 corners deadlocks with 64- and 256-word
    // FIFOs (a ray has one message in flight, but a corner many rays); with the limit it cannot.
    const PreparedScene balls = prepare(load_scene("balls:1"), 50);
    const RenderOptions opt = small(24);
    const RenderResult native = render_native(balls, opt);
    for (std::size_t cap : {64, 256}) {
        INFO("balls:1, capacity " << cap);
        machine::Options mo = model(machine::Model::V);
        mo.fifo_capacity = cap;
        CHECK_THROWS_WITH(machine::render(balls, opt, mo), Catch::Contains("deadlock") &&
                                                            Catch::Contains(fmt_slots(cap)));
        mo.ray_slots = machine::deadlock_free_ray_slots(cap);
        const machine::Result r = machine::render(balls, opt, mo);
        require_same_result(native, r.render);
        require_accounting(r.machine);
        CHECK(r.machine.max_fifo_words <= 12 * static_cast<std::size_t>(mo.ray_slots));
    }
    // Big ray trees (gears): at the smallest capacity it deadlocks even with a window of 1 corner,
    // so no window works there (mount, with refraction, gets through at 1 corner: capacity counts
    // the words sent by the sender's cycle, not those a producer running ahead has queued); the
    // ray limit works on every model.
    for (const char* name : {"mount:1", "gears:1"}) {
        const PreparedScene prep = prepare(load_scene(name), 20);
        const RenderOptions o = small(12);
        const RenderResult nat = render_native(prep, o);
        machine::Options one_corner = model(machine::Model::V);
        one_corner.fifo_capacity = 16;
        one_corner.window = 1;
        if (std::string(name) == "gears:1")
            CHECK_THROWS_WITH(machine::render(prep, o, one_corner), Catch::Contains("deadlock"));
        else
            require_same_result(nat, machine::render(prep, o, one_corner).render);
        for (machine::Model m : {machine::Model::V, machine::Model::M, machine::Model::S})
            for (std::size_t cap : {16, 64}) {
                INFO(name << " model " << machine::model_name(m) << ", capacity " << cap);
                machine::Options mo = model(m);
                mo.fifo_capacity = cap;
                mo.ray_slots = machine::deadlock_free_ray_slots(cap);
                const machine::Result r = machine::render(prep, o, mo);
                require_same_result(nat, r.render);
                CHECK(r.machine.max_fifo_words <= cap);
            }
    }
}

TEST_CASE("Bad machine options and data that do not fit are clear errors", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("tetra:1"), 4);
    machine::Options mo = model(machine::Model::V);
    mo.fifo_capacity = 8;
    CHECK_THROWS_WITH(machine::render(prep, small(4), mo), Catch::Contains("at least 16 words"));
    mo = model(machine::Model::V);
    mo.pes = 0;
    CHECK_THROWS_WITH(machine::render(prep, small(4), mo), Catch::Contains("at least one PE"));
    mo = model(machine::Model::V);
    mo.cache.enabled = true;
    mo.cache.line = 24;
    CHECK_THROWS_WITH(machine::render(prep, small(4), mo), Catch::Contains("power of two"));
    mo = model(machine::Model::V);
    mo.ray_slots = 5000;
    CHECK_THROWS_WITH(machine::render(prep, small(4), mo), Catch::Contains("ray slots must be 1 to 4096"));
    mo = model(machine::Model::V);
    mo.max_cycles = 1000;
    CHECK_THROWS_WITH(machine::render(prep, small(8), mo), Catch::Contains("cycle limit"));
    const PreparedScene big = prepare(load_scene("tetra:1"), 125); // 127^3 map bytes > SRAM
    CHECK_THROWS_WITH(machine::render(big, small(2), model(machine::Model::V)), Catch::Contains("does not fit the OS SRAM"));
}

TEST_CASE("Two runs of one render have the same result digest (host times are left out)", "[unit][machine]") {
    const PreparedScene a = prepare(load_scene("tetra:1"), 6), b = prepare(load_scene("tetra:1"), 6);
    const RenderOptions opt = small(8);
    const machine::Options mo = model(machine::Model::V);
    const nlohmann::json ja = machine::stats_json(a, opt, mo, machine::render(a, opt, mo));
    const nlohmann::json jb = machine::stats_json(b, opt, mo, machine::render(b, opt, mo));
    CHECK(ja != jb); // the host times differ...
    CHECK(machine::result_digest(ja) == machine::result_digest(jb)); // ...and nothing else
}

// Every key keeps one type whatever the run (docs/stats-json.md): a reader never has to ask
// whether `machine.cache` is a string this time.
TEST_CASE("A stats JSON key has one type in every kind of run", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("balls:1"), 4);
    const RenderOptions opt = small(8);
    std::vector<nlohmann::json> runs = {stats_json(prep, opt, render_native(prep, opt), "native")};
    std::vector<machine::Options> configs;
    configs.push_back(model(machine::Model::V));
    configs.push_back(model(machine::Model::M));
    configs.back().cache.enabled = true;
    configs.push_back(model(machine::Model::V));
    configs.back().pes = 2;
    configs.back().dynamic_balance = true;
    configs.push_back(model(machine::Model::V));
    configs.back().fifo_capacity = 24;
    configs.back().ray_slots = 2;
    configs.push_back(model(machine::Model::V));
    configs.back().os_machine = "os-real";
    configs.back().ic_machine = "ic-real";
    for (const machine::Options& mo : configs) runs.push_back(machine::stats_json(prep, opt, mo, machine::render(prep, opt, mo)));
    std::map<std::string, std::pair<nlohmann::json::value_t, std::size_t>> seen; // path (array indices left out) -> type, run
    auto walk = [&](auto& self, const nlohmann::json& v, const std::string& path, std::size_t run) -> void {
        if (v.is_object()) {
            for (const auto& [key, child] : v.items()) self(self, child, path + "." + key, run);
        } else if (v.is_array()) {
            for (const nlohmann::json& child : v) self(self, child, path + "[]", run);
        }
        // Integers are written unsigned or signed by their value: both are JSON integers.
        const auto type = v.is_number_integer() ? nlohmann::json::value_t::number_integer : v.type();
        const auto [at, added] = seen.emplace(path, std::pair{type, run});
        INFO(path << " in run " << run << " and run " << at->second.second);
        CHECK((added || at->second.first == type));
    };
    for (std::size_t k = 0; k < runs.size(); ++k) {
        CHECK(runs[k]["schema"] == kStatsSchema);
        walk(walk, runs[k], "", k);
    }
    CHECK(runs[2]["machine"]["cache"]["enabled"] == true);
    CHECK(runs[1]["machine"]["cache"]["enabled"] == false);
    CHECK(runs[3]["machine"]["balance"]["mode"] == "dynamic");
    CHECK(runs[5]["machine"].contains("kernels"));
}

TEST_CASE("Stats JSON and trace of a small scene (golden cycles)", "[unit][machine]") {
    const PreparedScene prep = prepare(load_scene("tetra:1"), 6);
    const RenderOptions opt = small(16);
    machine::Options mo = model(machine::Model::V);
    const std::string trace_path = (std::filesystem::temp_directory_path() / "nesshi_machine_test_trace.json").string();
    mo.trace_json = trace_path; // not the working directory: a run by hand would litter the checkout
    const machine::Result r = machine::render(prep, opt, mo);
    nlohmann::json j = machine::stats_json(prep, opt, mo, r);
    for (const char* stage : {"os", "ic", "sc"})
        for (const char* key : {"processing", "communication", "wait", "bundles", "ops", "ilp", "utilization"})
            CHECK(j["cycles"][stage].contains(key));
    CHECK(j["host"].contains("bundles_per_second"));
    CHECK(j["host"]["simulated_bundles"].get<std::uint64_t>() == r.machine.simulated_bundles);
    // Traversal: the machine counts rays per kind, not voxel steps or tests: only `rays`, no fake 0s.
    const nlohmann::json native = stats_json(prep, opt, render_native(prep, opt), "native");
    REQUIRE(j["traversal"].size() == 4);
    for (const auto& [kind, counters] : j["traversal"].items()) {
        INFO(kind);
        CHECK(counters == nlohmann::json{{"rays", native["traversal"][kind]["rays"]}});
        CHECK(native["traversal"][kind].contains("voxel_steps"));
    }
    CHECK(j["traversal"]["eye"]["rays"].get<std::uint64_t>() == 17 * 17);
    // The stages' processor detail agrees with their cycles (one PE: the sum is that PE's).
    for (const char* st : {"os", "ic"}) {
        INFO(st);
        const nlohmann::json& d = j["detail"][st];
        CHECK(d["processing_cycles"] == j["cycles"][st]["processing"]);
        CHECK(d["communication_cycles"] == j["cycles"][st]["communication"]);
        CHECK(d["wait_cycles"] == j["cycles"][st]["wait"]);
        std::uint64_t hist = 0;
        for (const auto& n : d["ilp_hist"]) hist += n.get<std::uint64_t>();
        CHECK(hist == j["cycles"][st]["bundles"].get<std::uint64_t>());
        CHECK(d["utilization"].get<double>() == Approx(j["cycles"][st]["utilization"].get<double>()));
        CHECK(!d["regions"].empty());
        CHECK(!d["hot"].empty());
    }
    // The golden part: everything but host timings.
    j.erase("host");
    CHECK(!j["grid"].contains("build_seconds")); // host time lives under "host"
    const std::string got = stats_text(j);
    const std::string path = std::string(NESSHI_TEST_DATA) + "/machine-tetra1-V.json";
    if (std::getenv("NESSHI_UPDATE_GOLDEN")) std::ofstream(path) << got;
    std::ifstream f(path);
    std::stringstream want;
    want << f.rdbuf();
    CHECK(got == want.str());
    std::ifstream t(trace_path);
    const nlohmann::json trace = nlohmann::json::parse(t);
    CHECK(trace["traceEvents"].size() > 10);
}
