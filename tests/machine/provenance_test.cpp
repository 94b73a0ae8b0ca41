// The provenance of a machine run: what its results depend on, and the differences named.
#include "machine/provenance.hpp"

#include "support.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

using namespace nesshi;

namespace {

rt::RenderOptions size(int n) {
    rt::RenderOptions ro;
    ro.width = ro.height = n;
    return ro;
}
} // namespace

TEST_CASE("Provenance names the scene, kernels, the machines the model uses and the options", "[unit][machine]") {
    machine::Options v;
    const machine::Provenance p = machine::provenance("tetra:1", 8, size(16), v);
    CHECK(p.at("scene") == "tetra:1");
    CHECK(p.at("grid") == "8");
    CHECK(p.at("scene.hash").size() == 16);
    CHECK(p.at("options.model") == "V");
    CHECK(p.at("options.size") == "16x16");
    CHECK(p.count("kernels.os/dda.s") == 1);
    CHECK(p.count("kernels.abi.inc") == 1);
    CHECK(p.at("machine.os").rfind("os ", 0) == 0);
    CHECK(p.count("machine.ic") == 1);
    CHECK(p.at("build") == machine::build_identity());
    CHECK(machine::build_identity().size() == 16);

    machine::Options m;
    m.model = machine::Model::M;
    const machine::Provenance pm = machine::provenance("tetra:1", 8, size(16), m);
    CHECK(pm.count("machine.os") == 0); // M runs both kernels on seq
    CHECK(pm.count("machine.ic") == 0);
    CHECK(pm.at("machine.seq") == p.at("machine.seq"));

    // The quantum changes no result: a cell run with another is the same result.
    machine::Options quantum = v;
    quantum.quantum = 7;
    const machine::Provenance pq = machine::provenance("tetra:1", 8, size(16), quantum);
    CHECK(pq.at("options.quantum") == "7");
    CHECK(p.at("options.quantum") == std::to_string(machine::Options::kQuantum));
    CHECK(machine::provenance_differences(p, pq).empty());

    machine::Options real = v;
    real.ic_machine = "ic-real";
    real.fifo_capacity = 64;
    const auto d = machine::provenance_differences(p, machine::provenance("tetra:1", 8, size(16), real));
    REQUIRE(d.size() == 2);
    CHECK(d[0].rfind("machine.ic: ic ", 0) == 0);
    CHECK(d[0].find(" -> ic-real ") != std::string::npos);
    CHECK(d[1] == "options.fifo_capacity: 0 -> 64");

    // A result of another build differs (its timing model may), unless the caller keeps it.
    machine::Provenance older = p;
    older["build"] = "0123456789abcdef";
    CHECK(machine::provenance_differences(older, p) ==
          std::vector<std::string>{"build: 0123456789abcdef -> " + machine::build_identity()});
    CHECK(machine::provenance_differences(older, p, false).empty());
    older.erase("build"); // a cell from before builds were told apart
    CHECK(machine::provenance_differences(older, p).size() == 1);
    // A cell of an older stats layout is another result even when the build is kept.
    machine::Provenance layout = p;
    layout.erase("stats_schema");
    CHECK(machine::provenance_differences(layout, p, false) ==
          std::vector<std::string>{fmt::format("stats_schema: (none) -> {}", rt::kStatsSchema)});

    // Another size factor is another scene text; the same spec hashes alike.
    CHECK(machine::provenance("tetra:2", 8, size(16), v).at("scene.hash") != p.at("scene.hash"));
    CHECK(machine::provenance("tetra:1", 8, size(16), v) == p);
    // A user's machine file is named by its path and told apart by its fingerprint.
    machine::Options user = v;
    user.os_machine = kData + "/os-3fpu.toml";
    const machine::Provenance pu = machine::provenance("tetra:1", 8, size(16), user);
    CHECK(pu.at("machine.os").rfind(user.os_machine.reference() + " ", 0) == 0);
    CHECK(pu.at("machine.os").substr(pu.at("machine.os").size() - 16) !=
          p.at("machine.os").substr(p.at("machine.os").size() - 16));
}

TEST_CASE("The result digest ignores host times, not results", "[unit][machine]") {
    const auto a = nlohmann::json::parse(R"({"cycles": {"total": 5}, "host": {"wall_seconds": 1.0}})");
    const auto b = nlohmann::json::parse(R"({"host": {"wall_seconds": 7.5}, "cycles": {"total": 5}, "digest": "x"})");
    const auto c = nlohmann::json::parse(R"({"cycles": {"total": 6}, "host": {"wall_seconds": 1.0}})");
    CHECK(machine::result_digest(a) == machine::result_digest(b));
    CHECK(machine::result_digest(a) != machine::result_digest(c));
}
