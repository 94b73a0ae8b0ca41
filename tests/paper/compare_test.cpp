// Machine runs side by side (paper/compare.hpp).
#include "paper/compare.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

using namespace nesshi;
using namespace nesshi::paper;

namespace {
std::string run(std::uint64_t total, std::uint64_t os_proc, double os_ilp, std::uint64_t loop_cycles,
                const std::string& scene = "tetra:1", const std::string& loop = "loop") {
    nlohmann::json j;
    j["scene"] = scene;
    j["size"] = {16, 16};
    j["detail"]["os"]["machine"] = "os";
    j["cycles"] = {{"total", total}, {"os", {{"processing", os_proc}, {"ilp", os_ilp}}}};
    j["detail"]["os"]["regions"] = {{{"label", "start"}, {"cycles", 10}}, {{"label", loop}, {"cycles", loop_cycles}}};
    return j.dump();
}
const std::vector<std::string>* row(const Table& t, const std::string& name) {
    for (const auto& r : t.rows)
        if (r[0] == name) return &r;
    return nullptr;
}
} // namespace

TEST_CASE("compare: each run's figures and their ratios to the first", "[unit][paper]") {
    const Comparison c = compare_runs({{"ideal", run(1000, 400, 2.5, 300)}, {"real", run(2300, 700, 1.25, 900)}});
    const Table& t = c.table;
    CHECK(c.warnings.empty());
    CHECK(t.header == std::vector<std::string>{"metric", "ideal", "real", "real / ideal"});
    REQUIRE(row(t, "cycles.total"));
    CHECK(*row(t, "cycles.total") == std::vector<std::string>{"cycles.total", "1000", "2300", "2.300"});
    CHECK(*row(t, "cycles.os.ilp") == std::vector<std::string>{"cycles.os.ilp", "2.500", "1.250", "0.500"});
    CHECK(*row(t, "detail.os.regions.loop.cycles") ==
          std::vector<std::string>{"detail.os.regions.loop.cycles", "300", "900", "3.000"});
    CHECK(row(t, "cycles.ic.processing") == nullptr); // no run has it
    CHECK(to_csv(t).find("cycles.total,1000,2300,2.300") != std::string::npos);
}

TEST_CASE("compare: three runs, what each is, a warning for other scenes, no ratio across other kernels",
          "[unit][paper]") {
    const Comparison c = compare_runs({{"a", run(1000, 400, 2.5, 300)},
                                       {"b", run(2000, 500, 2.0, 8000, "tetra:1", "__sa_kernel")},
                                       {"c", run(3000, 600, 2.0, 600, "balls:1")}});
    const Table& t = c.table;
    CHECK(t.header == std::vector<std::string>{"metric", "a", "b", "c", "b / a", "c / a"});
    CHECK(*row(t, "run.scene") == std::vector<std::string>{"run.scene", "tetra:1", "tetra:1", "balls:1", "same", "differs"});
    CHECK(*row(t, "run.size") == std::vector<std::string>{"run.size", "16x16", "16x16", "16x16", "same", "same"});
    CHECK(row(t, "run.ic_machine") == nullptr); // no run names one
    REQUIRE(c.warnings.size() == 1);
    CHECK(c.warnings[0] == "the runs are of different scenes (tetra:1, tetra:1, balls:1): their cycles do not compare");
    CHECK(*row(t, "cycles.total") == std::vector<std::string>{"cycles.total", "1000", "2000", "3000", "2.000", "3.000"});
    // b's kernel is another (its loop rescheduled): its regions are shown, not divided by a's.
    CHECK(*row(t, "detail.os.regions.start.cycles") ==
          std::vector<std::string>{"detail.os.regions.start.cycles", "10", "10", "10", "—", "1.000"});
    CHECK(*row(t, "detail.os.regions.loop.cycles") ==
          std::vector<std::string>{"detail.os.regions.loop.cycles", "300", "—", "600", "—", "2.000"});
    CHECK(row(t, "detail.os.regions.__sa_kernel.cycles"));
}

TEST_CASE("compare: a file that is not a machine run is an error naming it", "[unit][paper]") {
    CHECK_THROWS_WITH(compare_runs({{"a.json", run(1, 1, 1, 1)}, {"b.json", "{\"rays\": 5}"}}),
                      Catch::StartsWith("b.json: error: not a machine run's stats JSON"));
    CHECK_THROWS_WITH(compare_runs({{"a.json", run(1, 1, 1, 1)}, {"b.json", "{"}}), Catch::StartsWith("b.json: error: not JSON"));
    CHECK_THROWS_WITH(compare_runs({{"a.json", run(1, 1, 1, 1)}}), Catch::Contains("two runs or more"));
}
