// The sweep spec, its cells and its tidy outputs (the runs themselves are checked from the CLI).
#include "paper/sweep.hpp"

#include "base/write_file.hpp"
#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

using namespace nesshi;
using namespace nesshi::paper;
using nesshi::test::TempDir;

namespace {

// A machine description at `path` (a copy of ic), for a spec that names it; returns the path.
std::string machine_file(const std::string& path) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    base::write_file(path, fmt::format("inherits = \"ic\"\nname = \"{}\"\n", std::filesystem::path(path).stem().string()));
    return path;
}

std::string error_of(const std::string& text) {
    try {
        parse_sweep_spec(text, "s.toml");
    } catch (const PaperError& e) {
        return e.what();
    }
    return "no error";
}

const char* kSpec = R"(metrics = ["cycles.total", "machine.cache.misses"]
[axes]
scene = ["balls:1", "tetra:1"]
size = 16
fifo_capacity = [0, 48, 24]
cache_size = 4096
[chart]
x = "fifo_capacity"
)";

std::string stats(std::uint64_t total) {
    return nlohmann::json{{"cycles", {{"total", total}}}, {"machine", {{"cache", {{"misses", 7}}}}}}.dump();
}

} // namespace

TEST_CASE("Sweep spec: the axes in the file's order, the product of the lists, checked values", "[unit][sweep]") {
    const SweepSpec s = parse_sweep_spec(kSpec, "s.toml");
    REQUIRE(s.axes.size() == 4);
    CHECK(s.axes[0].name == "scene");
    CHECK(s.axes[2].name == "fifo_capacity");
    CHECK(s.axes[2].values == std::vector<std::string>{"0", "48", "24"});
    const std::vector<SweepCell> cells = sweep_cells(s);
    REQUIRE(cells.size() == 6);
    CHECK(cells[1].values == std::vector<std::string>{"balls:1", "16", "48", "4096"});
    CHECK(cells[0].id != cells[1].id);
    CHECK(sweep_cells(s)[1].id == cells[1].id); // stable
    const SweepRunInputs in = sweep_inputs(s, cells[1]);
    CHECK(in.render.width == 16);
    CHECK(in.machine.fifo_capacity == 48);
    CHECK(in.machine.cache.enabled); // a cache_* axis turns the cache on
    CHECK(in.machine.cache.bytes == 4096);
    CHECK(in.machine.ray_slots == 4); // as render does: 48 / 12 rays in flight
    CHECK(sweep_inputs(s, cells[0]).machine.ray_slots == 0);
    CHECK(s.metrics == std::vector<std::string>{"cycles.total", "machine.cache.misses"});
    CHECK(parse_sweep_spec("[axes]\nscene = \"tetra:1\"\n", "s.toml").metrics == default_sweep_metrics());
}

TEST_CASE("Sweep spec: bad input is a located error", "[unit][sweep]") {
    CHECK_THAT(error_of("[axes]\nfifo_depth = [1, 2]\n"), Catch::StartsWith("s.toml:2:1: error: unknown axis 'fifo_depth'"));
    CHECK_THAT(error_of("[axes]\nsize = []\n"), Catch::StartsWith("s.toml:2:8: error: size: empty list"));
    CHECK_THAT(error_of("[axes]\nsize = 1.5\n"), Catch::Contains("a value must be a string, a whole number or a boolean"));
    CHECK_THAT(error_of("[axes]\npes = [1, 0]\n"), Catch::Contains("pes = 0: must be a whole number from 1 to 64"));
    CHECK_THAT(error_of("[axes]\nmodel = \"X\"\n"), Catch::Contains("model = X: must be S, M or V"));
    CHECK_THAT(error_of("[axes]\nresident = \"yes\"\n"), Catch::Contains("resident = yes: must be true or false"));
    CHECK_THAT(error_of("frobs = 1\n[axes]\nsize = 8\n"), Catch::StartsWith("s.toml:1:1: error: unknown key 'frobs'"));
    CHECK_THAT(error_of("metrics = \"cycles.total\"\n[axes]\nsize = 8\n"), Catch::Contains("'metrics' must be a list of strings"));
    CHECK_THAT(error_of("metrics = []\n"), Catch::Contains("no [axes]"));
    CHECK_THAT(error_of("[axes]\nsize = 8\n[chart]\nx = \"grid\"\n"), Catch::Contains("chart x 'grid' is not one of the spec's axes"));
    CHECK_THAT(error_of("[axes\n"), Catch::StartsWith("s.toml:1:"));
    CHECK_THAT(error_of("[axes]\nsize = 8\n[chart]\ny_scale = \"cubic\"\n"), Catch::Contains("y_scale is \"linear\" or \"log\""));
    CHECK(parse_sweep_spec("[axes]\nsize = 8\n[chart]\ny_scale = \"log\"\n", "s.toml").chart_log_y);
    // Found by fuzzing (crashes/sweep/axis-value-twice): a value twice made two cells of one file.
    CHECK_THAT(error_of("[axes]\nsize = [4, 8, 4]\n"), Catch::StartsWith("s.toml:2:15: error: size: 4 is listed twice"));
}

TEST_CASE("Sweep spec: an axis that changes nothing on a model it sweeps is a located error", "[unit][sweep]") {
    CHECK_THAT(error_of("[axes]\nmodel = [\"V\", \"S\"]\nfifo_latency = [0, 4]\n"),
               Catch::StartsWith("s.toml:3:16: error: fifo_latency has no effect on model S"));
    CHECK_THAT(error_of("[axes]\nmodel = \"S\"\nquantum = 8\n"), Catch::Contains("quantum has no effect on model S"));
    CHECK(error_of("[axes]\nmodel = [\"V\", \"M\"]\nfifo_latency = [0, 4]\n") == "no error");
}

TEST_CASE("Sweep spec: file values are relative to the spec's folder, presets and built-in scenes are names",
          "[unit][sweep]") {
    const TempDir t; // the spec's machines load as it is parsed: they must exist
    const std::string root = t.str(), relative = machine_file(root + "/specs/m/x.toml"), absolute = machine_file(root + "/abs/y.toml");
    const SweepSpec s = parse_sweep_spec(fmt::format("[axes]\nscene = [\"tetra:1\", \"my.nff\"]\nos_machine = [\"os-real\", "
                                                     "\"m/x.toml\", \"{}\"]\nkernels = \"k\"\n",
                                                     absolute),
                                         root + "/specs/s.toml");
    REQUIRE(s.axes.size() == 3);
    CHECK(s.axes[0].values == std::vector<std::string>{"tetra:1", root + "/specs/my.nff"});
    CHECK(s.axes[1].values == std::vector<std::string>{"os-real", relative, absolute});
    CHECK(s.axes[2].values == std::vector<std::string>{root + "/specs/k"});
    // A machine that does not load is the spec's error, at its value.
    CHECK_THAT(error_of("[axes]\nic_machine = [\"ic\", \"nosuch.toml\"]\n"),
               Catch::StartsWith("s.toml:2:21: error: ic_machine = nosuch.toml: nosuch.toml: error: no such machine preset or file"));
}

// Findings S1-S3 of the robustness campaign (issue 24).
TEST_CASE("Sweep spec: unknown metric paths are located errors", "[unit][sweep]") {
    for (const char* bad : {"no.such.path", "", ".", "cycles..total", "cycles.os", "cycles.total."}) {
        INFO(bad);
        CHECK_THAT(error_of(fmt::format("metrics = [\"cycles.total\", \"{}\"]\n[axes]\nsize = 8\n", bad)),
                   Catch::StartsWith("s.toml:1:28: error: unknown metric '" + std::string(bad) + "'"));
    }
    CHECK_THAT(error_of("[axes]\nsize = 8\n[chart]\ny = \"cycles.totl\"\n"),
               Catch::StartsWith("s.toml:4:5: error: unknown metric 'cycles.totl'"));
    for (const char* good : {"cycles.s_cycles", "machine.cache.misses", "machine.kernels.os.nops_inserted", "host.wall_seconds",
                             "detail.os.taken_branches", "machine.ray_slots"}) {
        INFO(good);
        CHECK(error_of(fmt::format("metrics = [\"{}\"]\n[axes]\nsize = 8\n", good)) == "no error");
    }
}

TEST_CASE("Sweep spec: a huge product is refused by name before any cell is planned", "[unit][sweep]") {
    std::string axes = "[axes]\n";
    for (const char* a : {"size", "pes", "window", "fifo_latency"}) {
        axes += std::string(a) + " = [";
        for (int v = 1; v <= 30; ++v) axes += (v > 1 ? ", " : "") + std::to_string(v);
        axes += "]\n";
    }
    const SweepSpec s = parse_sweep_spec(axes, "s.toml"); // each value checked alone: fast
    CHECK(sweep_cell_count(s) == 810'000);
    CHECK(sweep_product(s) == "size 30 x pes 30 x window 30 x fifo_latency 30");
    SweepOptions o;
    o.out_dir = "unused";
    CHECK_THROWS_WITH(run_sweep(s, o), Catch::StartsWith("s.toml: error: 810000 cells (size 30 x pes 30 x window 30 x "
                                                         "fifo_latency 30): more than 10000 (allow them with --max-cells 810000"));
}

TEST_CASE("Sweep spec: every cell has a cycle limit, from the pixels or a max_cycles axis", "[unit][sweep]") {
    const SweepSpec s = parse_sweep_spec("[axes]\nsize = [4, 8]\n", "s.toml");
    CHECK(sweep_inputs(s, sweep_cells(s)[1]).machine.max_cycles == kSweepCyclesPerPixel * 64);
    const SweepSpec l = parse_sweep_spec("[axes]\nsize = 4\nmax_cycles = [1000, 5000]\n", "s.toml");
    CHECK(sweep_inputs(l, sweep_cells(l)[1]).machine.max_cycles == 5000);
    CHECK_THAT(error_of("[axes]\nmax_cycles = 0\n"), Catch::Contains("max_cycles = 0: must be a whole number from 1"));
}

TEST_CASE("Sweep outputs: tidy rows typed as written, missing metrics empty, a chart per series", "[unit][sweep]") {
    const SweepSpec s = parse_sweep_spec(kSpec, "s.toml");
    const std::vector<SweepCell> cells = sweep_cells(s);
    std::vector<std::string> json(cells.size());
    json[0] = stats(100);
    json[1] = stats(90);
    json[2] = nlohmann::json{{"cycles", {{"total", 95}}}}.dump(); // no cache numbers
    // cells 3..5 (tetra) have no result: left out
    const std::string csv = sweep_csv(s, cells, json);
    CHECK(csv.substr(0, csv.find('\n')) == "cell,scene,size,fifo_capacity,cache_size,cycles.total,machine.cache.misses");
    CHECK(csv.find(cells[1].id + ",balls:1,16,48,4096,90,7\n") != std::string::npos);
    CHECK(csv.find(cells[2].id + ",balls:1,16,24,4096,95,\n") != std::string::npos);
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 4);
    const std::vector<std::string> rows = sweep_jsonl(s, cells, json);
    REQUIRE(rows.size() == 3);
    const nlohmann::json r = nlohmann::json::parse(rows[2]);
    CHECK(r["scene"] == "balls:1");
    CHECK(r["fifo_capacity"].is_number_integer());
    CHECK(r["cycles.total"] == 95);
    CHECK(r["machine.cache.misses"].is_null());
    const std::string svg = sweep_chart_svg(s, cells, json);
    CHECK(svg.find("cycles.total against fifo_capacity") != std::string::npos);
    CHECK(svg.find("scene=balls:1") != std::string::npos); // one series per other swept axis value
    CHECK(svg.find(">24</text>") < svg.find(">48</text>")); // numeric x in ascending order
    const auto unbounded = svg.find(">unbounded</text>");   // capacity 0 (no limit) last, named
    REQUIRE(unbounded != std::string::npos);
    CHECK(svg.find(">48</text>") < unbounded);
    CHECK(std::count(svg.begin(), svg.end(), '<' ) > 10);
    CHECK(svg.find("log scale") == std::string::npos);

    // y_scale = "log": 1-2-5 ticks from below the least value to above the greatest (90..100 here).
    SweepSpec log_spec = s;
    log_spec.chart_log_y = true;
    const std::string log_svg = sweep_chart_svg(log_spec, cells, json);
    CHECK(log_svg.find("cycles.total against fifo_capacity (log scale)") != std::string::npos);
    CHECK(log_svg.find(">50</text>") != std::string::npos);
    CHECK(log_svg.find(">100</text>") != std::string::npos);
    CHECK(log_svg.find(">200</text>") == std::string::npos);
    CHECK(log_svg.find(">20</text>") == std::string::npos);
}

TEST_CASE("Sweep chart: machines as a categorical axis, series apart without colour, labels that do not collide",
          "[unit][sweep]") {
    const TempDir t;
    machine_file(t.str() + "/machines/ic-with-a-rather-long-file-name.toml");
    const SweepSpec s = parse_sweep_spec("[axes]\nscene = [\"balls:1\", \"tetra:1\"]\nic_machine = [\"ic\", "
                                         "\"machines/ic-with-a-rather-long-file-name.toml\", \"ic-real\"]\n"
                                         "[chart]\nx = \"ic_machine\"\n",
                                         t.str() + "/s.toml");
    const std::vector<SweepCell> cells = sweep_cells(s);
    REQUIRE(cells.size() == 6);
    std::vector<std::string> json;
    for (std::uint64_t t : {100000, 2000, 120000, 2400, 150000, 3000}) json.push_back(stats(t));
    const std::string svg = sweep_chart_svg(s, cells, json);
    CHECK(svg.find(">ic-with-a-rather-long-file-name</text>") != std::string::npos); // a file by its stem
    CHECK(svg.find("machines/") == std::string::npos);
    CHECK(svg.find("rotate(-30") != std::string::npos);                            // long labels turn
    CHECK(svg.find("fill=\"none\" stroke") == std::string::npos);                  // no lines across machines
    CHECK(svg.find("<circle") != std::string::npos);                                // two series: two shapes
    CHECK(svg.find("<rect x=") != std::string::npos);
    CHECK(svg.find("(log scale: values span 75x)") != std::string::npos);          // 2000 .. 150000

    // A spec that says y_scale = "linear" gets it; a series equal to another says so.
    SweepSpec lin = s;
    lin.chart_scale_given = true;
    CHECK(sweep_chart_svg(lin, cells, json).find("log scale") == std::string::npos);
    std::vector<std::string> equal;
    for (std::uint64_t t : {100, 120, 150, 100, 120, 150}) equal.push_back(stats(t));
    CHECK(sweep_chart_svg(s, cells, equal).find("scene=tetra:1 (the same as above)") != std::string::npos);
}
