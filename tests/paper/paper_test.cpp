// `nesshi paper` without the simulator: published data, cell files, the resumable runner (with a
// stand-in cell runner), tables, chart and summary from synthetic cells.
#include "paper/paper.hpp"
#include "paper/published.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <mutex>
#include <random>
#include <set>

using namespace nesshi;
using namespace nesshi::rt;
using namespace nesshi::paper;
namespace fs = std::filesystem;
using nesshi::test::TempDir;

namespace {

using machine::StageCycles;

// A stage of `units` issue slots with `ilp` operations per processing cycle.
StageCycles stage_of(std::uint64_t processing, std::uint64_t communication, double ilp, std::uint64_t units) {
    StageCycles s{processing, communication};
    s.processing_ops = static_cast<std::uint64_t>(std::llround(ilp * static_cast<double>(processing)));
    s.units = units;
    return s;
}

// The shape of machine::stats_json's output that the paper module reads.
std::string cell_json(machine::Model m, int size, std::uint64_t total, const StageCycles& os, const StageCycles& ic,
                      const StageCycles& sc, std::uint64_t s_cycles = 0) {
    nlohmann::json j;
    j["schema"] = rt::kStatsSchema;
    j["model"] = machine::model_name(m);
    j["size"] = {size, size};
    j["cycles"] = {{"total", total},
                   {"os", machine::stage_cycles_json(os)},
                   {"ic", machine::stage_cycles_json(ic)},
                   {"sc", machine::stage_cycles_json(sc)}};
    if (m == machine::Model::M) j["cycles"]["s_cycles"] = s_cycles;
    j["host"] = {{"wall_seconds", 1.5}};
    return j.dump(2);
}


// Synthetic but paper-like cells: the V time falls with the grid until OS outgrows IC at `best`.
CellRecord synthetic(const std::string& scene, int grid, machine::Model m, int size, int best) {
    const std::uint64_t mega = 1'000'000;
    const std::uint64_t os = static_cast<std::uint64_t>(grid) * 10 * mega;
    const std::uint64_t ic = static_cast<std::uint64_t>(best) * best * 10 * mega / static_cast<std::uint64_t>(grid);
    const std::uint64_t sc = 5 * mega, factor = m == machine::Model::M ? 2 : 1;
    CellRecord r;
    r.key = {scene, grid, m, size};
    r.os = stage_of(os * factor, os / 10 * factor, 2.28, 4);
    r.ic = stage_of(ic * factor, ic / 10 * factor, 2.05, 4);
    r.sc = stage_of(sc, sc / 5, 1, 1);
    r.total = std::max(r.os.load(), r.ic.load()) + r.sc.load();
    if (m == machine::Model::M) r.s_cycles = r.os.load() + r.ic.load() + r.sc.load();
    return r;
}

PaperData synthetic_data(int size, const std::vector<std::string>& scenes = {"tetra", "balls"}) {
    PaperOptions o;
    o.size = size;
    o.scenes = scenes;
    std::vector<CellRecord> cells;
    for (const std::string& s : scenes)
        for (int g : o.grids)
            for (machine::Model m : {machine::Model::V, machine::Model::M})
                cells.push_back(synthetic(s, g, m, size, s == "tetra" ? 50 : 100));
    PaperData d = make_data(o, std::move(cells));
    d.auto_grid["tetra"] = 50;
    d.auto_grid["balls"] = 70;
    d.prepass_grid["tetra"] = 50;
    d.prepass_grid["balls"] = 50;
    d.prepass_size = 100;
    return d;
}

// A printed published value: "≈4900*" -> 4900.
double number(std::string s) {
    if (s.rfind("≈", 0) == 0) s.erase(0, std::string("≈").size());
    return std::stod(s); // stops at the trailing *
}

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

std::string read(const fs::path& p) {
    std::ifstream f(p);
    return {std::istreambuf_iterator<char>(f), {}};
}

// A stand-in for simulate_cell: counts its calls and returns a valid cell.
struct FakeRunner {
    std::atomic<int> calls{0};
    std::mutex mutex;
    std::set<std::string> ran;
    std::string fail_scene; // cells of this scene throw
    CellRunner fn() {
        return [this](const CellKey& k, const CellProgressFn& progress) {
            ++calls;
            {
                std::lock_guard lock(mutex);
                ran.insert(cell_file_name(k));
            }
            if (progress) progress(1, 2);
            if (k.scene == fail_scene) throw std::runtime_error("kernel fault");
            CellRecord r = synthetic(k.scene, k.grid, k.model, k.size, 50);
            return cell_json(k.model, k.size, r.total, r.os, r.ic, r.sc, r.s_cycles);
        };
    }
};

PaperOptions small_options(const std::string& out) {
    PaperOptions o;
    o.size = 8;
    o.scenes = {"tetra:1", "mount:1"};
    o.grids = {4, 8};
    o.out_dir = out;
    o.threads = 2;
    return o;
}

} // namespace

TEST_CASE("Published tables: every scene x grid once, speed-ups agree with the times", "[paper]") {
    CHECK(published_times().size() == 15);
    CHECK(published_stages().size() == 15);
    CHECK(published_vliw().size() == 5);
    for (const PublishedTimes& p : published_times()) {
        INFO(p.scene << " " << p.grid);
        CHECK(find_published_times(p.scene, p.grid) == &p);
        REQUIRE(find_published_stages(p.scene, p.grid));
        // The printed speed-ups are rounded quotients of the printed times (where both were legible).
        CHECK(p.m.value / p.v.value == Approx(p.m_over_v.value).epsilon(0.03));
        CHECK(p.s.value / p.v.value == Approx(p.s_over_v.value).epsilon(0.03));
    }
    CHECK(find_published_times("tetra", 4) == nullptr);
    CHECK(find_published_times("balls", 20)->s.reconstructed);
    CHECK(find_published_times("mount", 20)->m.approximate);
    CHECK_FALSE(find_published_times("balls", 50)->s.reconstructed);
    CHECK(find_published_vliw("balls")->ic_ilp.lo == 2.01);
}

TEST_CASE("Cell files: names, parsing, clear errors naming the file", "[paper]") {
    CHECK(cell_file_name({"balls", 20, machine::Model::V, 512}) == "balls-g20-V-512.json");
    CHECK(cell_file_name({"tetra:1", 4, machine::Model::M, 8}) == "tetra_1-g4-M-8.json");
    CHECK(cell_file_name({"scenes/my scene.nff", 10, machine::Model::V, 64}) == "my_scene-g10-V-64.json");

    const CellKey key{"tetra", 20, machine::Model::M, 64};
    const std::string good =
        cell_json(machine::Model::M, 64, 900, {100, 20, 5, 1, 1}, {400, 30, 0, 1, 1}, {50, 10, 0, 1, 1}, 610);
    CellRecord r = parse_cell(key, good, "c.json");
    CHECK(r.total == 900);
    CHECK(r.s_cycles == 610);
    CHECK(r.os.load() == 120);
    CHECK(r.ic.processing == 400);
    CHECK(r.sc.communication == 10);
    CHECK(r.wall_seconds == 1.5);

    auto error_of = [&](const std::string& text, const CellKey& k) {
        try {
            parse_cell(k, text, "out/cells/x.json");
        } catch (const PaperError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(error_of("{\"cycles\": ", key), Catch::StartsWith("out/cells/x.json: error: malformed cell file"));
    CHECK_THAT(error_of("{\"cycles\": {\"total\": 5}}", key), Catch::Contains("missing \"cycles.s_cycles\""));
    nlohmann::json j = nlohmann::json::parse(good);
    j["cycles"]["ic"].erase("wait");
    CHECK_THAT(error_of(j.dump(), key), Catch::Contains("out/cells/x.json") && Catch::Contains("cycles.ic.wait"));
    j = nlohmann::json::parse(good);
    j["cycles"]["total"] = -3;
    CHECK_THAT(error_of(j.dump(), key), Catch::Contains("\"cycles.total\" is not a cycle count"));
    // A file copied under another cell's name does not pass for it.
    CHECK_THAT(error_of(good, {"tetra", 20, machine::Model::V, 64}), Catch::Contains("holds model M, expected V"));
    CHECK_THAT(error_of(good, {"tetra", 20, machine::Model::M, 512}), Catch::Contains("holds size 64, expected 512"));
}

TEST_CASE("Matrix: V and M per scene x grid, S alone still runs M", "[paper]") {
    PaperOptions o;
    o.scenes = {"tetra"};
    o.grids = {50, 20, 50};
    CHECK(matrix_cells(o).size() == 4); // grids sorted and de-duplicated
    CHECK(matrix_cells(o)[0] == CellKey{"tetra", 20, machine::Model::V, 512});
    o.models = {machine::Model::S};
    REQUIRE(matrix_cells(o).size() == 2);
    CHECK(matrix_cells(o)[0].model == machine::Model::M);
    o.models = {machine::Model::V};
    CHECK(matrix_cells(o)[1] == CellKey{"tetra", 50, machine::Model::V, 512});
}

TEST_CASE("Options: unknown scene, bad grid or size are errors", "[paper]") {
    PaperOptions o;
    CHECK_NOTHROW(validate(o));
    o.scenes = {"tetra", "nope"};
    CHECK_THROWS_WITH(validate(o), Catch::Contains("unknown scene 'nope'"));
    o.scenes = {"balls:x"};
    CHECK_THROWS_WITH(validate(o), Catch::Contains("bad size factor"));
    o.scenes = {"balls:2"};
    o.grids = {20, 0};
    CHECK_THROWS_WITH(validate(o), Catch::Contains("bad grid 0"));
    o.grids = {20};
    o.size = 0;
    CHECK_THROWS_WITH(validate(o), Catch::Contains("bad size 0"));
}

TEST_CASE("Runner: cells are written, and a second run loads them instead of running", "[paper]") {
    TempDir dir;
    const PaperOptions o = small_options(dir.str());
    FakeRunner first;
    std::size_t finished_events = 0;
    PaperOptions counted = o;
    counted.progress = [&](const PaperProgress& p) { finished_events += p.record != nullptr; };
    MatrixResult a = run_matrix(counted, first.fn());
    CHECK(first.calls == 8); // 2 scenes x 2 grids x (V, M)
    CHECK(a.run == 8);
    CHECK(a.loaded == 0);
    CHECK(finished_events == 8);
    REQUIRE(a.cells.size() == 8);
    for (const CellKey& k : matrix_cells(o)) CHECK(fs::exists(dir.path / "cells" / cell_file_name(k)));
    CHECK(std::none_of(fs::directory_iterator(dir.path / "cells"), fs::directory_iterator(),
                       [](const fs::directory_entry& e) { return e.path().extension() == ".tmp"; }));

    FakeRunner second;
    MatrixResult b = run_matrix(o, second.fn());
    CHECK(second.calls == 0);
    CHECK(b.loaded == 8);
    REQUIRE(b.cells.size() == 8);
    for (std::size_t i = 0; i < 8; ++i) {
        CHECK(b.cells[i].key == a.cells[i].key);
        CHECK(b.cells[i].total == a.cells[i].total);
    }

    // Only a missing cell runs again.
    const std::string gone = cell_file_name({"mount:1", 8, machine::Model::M, 8});
    fs::remove(dir.path / "cells" / gone);
    FakeRunner third;
    MatrixResult c = run_matrix(o, third.fn());
    CHECK(third.calls == 1);
    CHECK(third.ran == std::set<std::string>{gone});
    CHECK(c.loaded == 7);
}

TEST_CASE("Runner: a malformed cell file is an error naming it, before anything runs", "[paper]") {
    TempDir dir;
    const PaperOptions o = small_options(dir.str());
    fs::create_directories(dir.path / "cells");
    const fs::path bad = dir.path / "cells" / cell_file_name({"mount:1", 4, machine::Model::V, 8});
    std::ofstream(bad) << "{\"cycles\": {\"total\": 12"; // cut short
    FakeRunner runner;
    CHECK_THROWS_WITH(run_matrix(o, runner.fn()), Catch::StartsWith(bad.string() + ": error: malformed cell file") &&
                                                      Catch::Contains("delete it to run the cell again"));
    CHECK(runner.calls == 0);
}

TEST_CASE("Runner: a failing cell is reported, the others are kept", "[paper]") {
    TempDir dir;
    PaperOptions o = small_options(dir.str());
    FakeRunner runner;
    runner.fail_scene = "mount:1";
    MatrixResult r = run_matrix(o, runner.fn());
    CHECK(r.run == 4);
    CHECK(r.cells.size() == 4);
    REQUIRE(r.failures.size() == 4);
    CHECK_THAT(r.failures[0], Catch::StartsWith("mount_1-g") && Catch::EndsWith(": kernel fault"));
    CHECK_FALSE(fs::exists(dir.path / "cells" / cell_file_name({"mount:1", 4, machine::Model::V, 8})));
}

TEST_CASE("Cell provenance: stamped with a digest, a changed run or a hand edit is caught", "[paper]") {
    const std::string good =
        cell_json(machine::Model::V, 64, 900, {100, 20, 5, 1, 1}, {400, 30, 0, 1, 1}, {50, 10, 0, 1, 1});
    const machine::Provenance a = {{"tool", "nesshi 1"}, {"machine.ic", "ic 01"}, {"grid", "20"}};
    const std::string stamped = stamp_cell(good, a);
    CHECK(stale_reasons(stamped, a, "c.json").empty());
    // The tool's version alone keeps a cell (refactors keep every result).
    machine::Provenance newer = a;
    newer["tool"] = "nesshi 2";
    CHECK(stale_reasons(stamped, newer, "c.json").empty());
    // Another build is a difference, unless its cells are kept on purpose (and counted).
    machine::Provenance rebuilt = a;
    rebuilt["build"] = "2";
    CHECK(stale_reasons(stamped, rebuilt, "c.json") == std::vector<std::string>{"build: (none) -> 2"});
    bool other = false;
    CHECK(stale_reasons(stamped, rebuilt, "c.json", &other).empty());
    CHECK(other);
    CHECK(stale_reasons(stamped, a, "c.json", &other).empty());
    CHECK_FALSE(other);
    rebuilt["grid"] = "50"; // kept only when nothing else differs
    CHECK(stale_reasons(stamped, rebuilt, "c.json", &other) == std::vector<std::string>{"grid: 20 -> 50"});
    CHECK_FALSE(other);
    machine::Provenance b = a;
    b["machine.ic"] = "ic-real 02";
    b["options.pes"] = "2";
    CHECK(stale_reasons(stamped, b, "c.json") ==
          std::vector<std::string>{"machine.ic: ic 01 -> ic-real 02", "options.pes: (none) -> 2"});
    CHECK(stale_reasons(good, a, "c.json") == std::vector<std::string>{"no provenance recorded"});
    // Host times may differ (they are not in the digest); a number may not.
    nlohmann::json j = nlohmann::json::parse(stamped);
    j["host"]["wall_seconds"] = 99.0;
    CHECK(stale_reasons(j.dump(2), a, "c.json").empty());
    j["cycles"]["total"] = 1;
    CHECK_THROWS_WITH(stale_reasons(j.dump(2), a, "out/c.json"),
                      Catch::StartsWith("out/c.json: error: its results do not match its digest"));
    CHECK(parse_cell({"tetra", 20, machine::Model::V, 64}, stamped, "c.json").total == 900);
}

// A cell an older nesshi wrote in another stats layout (schema 1: no processing_ops) is not read:
// its provenance has no stats_schema, so it runs again instead of failing as malformed.
TEST_CASE("Runner: a cell of an older stats layout runs again, unread", "[paper]") {
    TempDir dir;
    PaperOptions o = small_options(dir.str());
    const CellProvenanceFn prov = [](const CellKey& k) {
        return machine::Provenance{{"scene", k.scene}, {"stats_schema", std::to_string(rt::kStatsSchema)}};
    };
    FakeRunner first;
    CHECK(run_matrix(o, first.fn(), prov).run == 8);
    const fs::path cell = dir.path / "cells" / cell_file_name({"tetra:1", 4, machine::Model::V, 8});
    nlohmann::json old = nlohmann::json::parse(read(cell));
    old.erase("schema");
    old.erase("digest");
    old["provenance"].erase("stats_schema");
    old["cycles"]["os"].erase("processing_ops");
    std::ofstream(cell) << stamp_cell(old.dump(), old["provenance"].get<machine::Provenance>());
    o.keep_other_builds = true; // even then
    FakeRunner second;
    const MatrixResult r = run_matrix(o, second.fn(), prov);
    CHECK(second.calls == 1);
    REQUIRE(r.stale.size() == 1);
    CHECK_THAT(r.stale[0], Catch::EndsWith(fmt::format("stats_schema: (none) -> {}", rt::kStatsSchema)));
}

TEST_CASE("Runner: a stored cell whose provenance differs runs again, and says why", "[paper]") {
    TempDir dir;
    const PaperOptions o = small_options(dir.str());
    std::string machine = "ic 01";
    const CellProvenanceFn prov = [&](const CellKey& k) {
        return machine::Provenance{{"scene", k.scene}, {"machine.ic", machine}};
    };
    FakeRunner first;
    CHECK(run_matrix(o, first.fn(), prov).run == 8);
    FakeRunner second;
    MatrixResult same = run_matrix(o, second.fn(), prov);
    CHECK(second.calls == 0);
    CHECK(same.stale.empty());
    machine = "ic-real 02";
    FakeRunner third;
    std::size_t stale_shown = 0;
    PaperOptions watched = o;
    watched.progress = [&](const PaperProgress& p) { stale_shown += p.stale ? p.stale->size() : 0; };
    MatrixResult changed = run_matrix(watched, third.fn(), prov);
    CHECK(third.calls == 8);
    CHECK(changed.loaded == 0);
    REQUIRE(changed.stale.size() == 8);
    CHECK(stale_shown == 8);
    CHECK_THAT(changed.stale[0], Catch::EndsWith(": machine.ic: ic 01 -> ic-real 02"));
    FakeRunner fourth; // the re-run cells now carry the new provenance
    CHECK(run_matrix(o, fourth.fn(), prov).loaded == 8);
    CHECK(fourth.calls == 0);
}

TEST_CASE("Derived numbers: load ratio, S time, best grid", "[paper]") {
    CellRecord v;
    v.os = {380, 20, 7};
    v.ic = {1900, 100, 0};
    v.sc = {90, 10, 3};
    CHECK(load_ratio(v) == std::array<int, 3>{4, 20, 1});
    CellRecord m = v;
    CHECK(s_time(m) == 2500); // no s_cycles: the sum of the loads
    m.s_cycles = 2600;
    CHECK(s_time(m) == 2600);
    CHECK(scale_to_paper(64) == 64.0);
    CHECK(paper_scene("balls:2") == "balls");
    CHECK(paper_scene("gears") == "");
    CHECK(is_paper_scene_size("mount"));
    CHECK(is_paper_scene_size("mount:6"));
    CHECK_FALSE(is_paper_scene_size("mount:1"));

    const PaperData d = synthetic_data(512);
    CHECK(best_grid(d, "tetra", machine::Model::V) == 50);
    CHECK(best_grid(d, "balls", machine::Model::V) == 100);
    CHECK(best_grid(d, "tree", machine::Model::V) == 0);
    CHECK(time_model(d) == machine::Model::V);
}

TEST_CASE("Number format: millions with 4 significant digits, no exponent", "[paper]") {
    CHECK(format_mcycles(16'846'000'000.0) == "16846");
    CHECK(format_mcycles(4'581'234.0) == "4.581");
    CHECK(format_mcycles(123.4) == "0.0001234");
    CHECK(format_mcycles(0) == "0");
}

TEST_CASE("Table 2: stages and load ratio beside the paper's", "[paper]") {
    const PaperData d = synthetic_data(512);
    const Table t = table2(d);
    REQUIRE(t.rows.size() == 6);
    CHECK(t.header.size() == t.rows[0].size());
    // tetra g50: OS 500+50, IC 500+50, SC 5+1 (millions) -> 92:92:1
    CHECK(t.rows[1][0] == "tetra");
    CHECK(t.rows[1][2] == "500.0");
    CHECK(t.rows[1][11] == "92:92:1");
    CHECK(t.rows[1].back() == "14:6:1"); // the paper's tetra 50
    CHECK(t.rows[1][t.rows[1].size() - 4] == "539");
    const std::string md = to_markdown(t);
    CHECK(contains(md, "## Table 2"));
    CHECK(contains(md, "| tetra | 50 | 500.0 |"));
    CHECK_FALSE(contains(md, "(512/")); // no scaling note at 512
    CHECK(contains(to_markdown(table2(synthetic_data(512, {"tree"}))),
                   "(?)")); // suspect printed ratio
    const std::string csv = to_csv(t);
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 7);
    CHECK(contains(csv, "scene,grid,size,os_processing,ic_processing,sc_processing,"));
    CHECK(contains(csv, "\ntetra,50,512,500000000,500000000,5000000,")); // cycles, not millions
}

// Issue 28: the CSVs are for programs: one header whatever the size, and every field but the
// scene and run names a plain number (or empty where a value is missing); flags and range ends
// have their own columns.
TEST_CASE("The tables' CSVs are tidy: fixed headers, plain numbers", "[paper]") {
    auto rows = [](const Table& t) {
        std::vector<std::vector<std::string>> out;
        std::istringstream in(to_csv(t));
        for (std::string line; std::getline(in, line);) {
            std::vector<std::string> f;
            std::istringstream l(line);
            for (std::string x; std::getline(l, x, ',');) f.push_back(x);
            if (!line.empty() && line.back() == ',') f.push_back("");
            out.push_back(f);
        }
        return out;
    };
    for (auto table : {&table2, &table3, &table4}) {
        const auto at512 = rows(table(synthetic_data(512, {"tetra", "balls", "tree"})));
        const auto at64 = rows(table(synthetic_data(64, {"tetra", "balls", "tree"})));
        CHECK(at512[0] == at64[0]);
        for (const auto* csv : {&at512, &at64})
            for (std::size_t r = 1; r < csv->size(); ++r) {
                REQUIRE((*csv)[r].size() == (*csv)[0].size());
                for (std::size_t c = 1; c < (*csv)[r].size(); ++c) {
                    const std::string& x = (*csv)[r][c];
                    INFO((*csv)[0][c] << " = '" << x << "'");
                    if (x.empty()) continue;
                    std::size_t used = 0;
                    (void)std::stod(x, &used);
                    CHECK(used == x.size());
                }
            }
    }
    // A reconstructed published value is a number with its flag beside it (balls 20: S 35173*).
    const auto t3 = rows(table3(synthetic_data(512)));
    const auto& h = t3[0];
    const std::size_t s = static_cast<std::size_t>(std::find(h.begin(), h.end(), "paper_s_m512") - h.begin());
    REQUIRE(s + 1 < h.size());
    CHECK(h[s + 1] == "paper_s_m512_reconstructed");
    for (const auto& r : t3)
        if (r[0] == "balls" && r[1] == "20") {
            CHECK(r[s] == "35173");
            CHECK(r[s + 1] == "1");
        }
}

TEST_CASE("Table 3: S from M, speed-ups, scaled columns and note when size != 512", "[paper]") {
    const PaperData d = synthetic_data(64);
    const Table t = table3(d);
    const std::vector<std::string> head = {"scene", "grid",  "S",   "M",   "V",  "S ×64",
                                           "M ×64", "V ×64", "S/M", "M/V", "S/V"};
    CHECK(std::equal(head.begin(), head.end(), t.header.begin()));
    const auto& balls20 = t.rows[3];
    REQUIRE(balls20[0] == "balls");
    // synthetic balls g20: V = 5000 + 500 + 6 = 5506 M; M = OS 400+40, IC 10000+1000, SC 6 -> 11006, S = 11446
    CHECK(balls20[2] == "11446");
    CHECK(balls20[3] == "11006");
    CHECK(balls20[4] == "5506");
    CHECK(balls20[7] == format_mcycles(5506e6 * 64));
    CHECK(balls20[8] == "1.04");
    CHECK(balls20[9] == "2.00");
    CHECK(balls20[10] == "2.08");
    CHECK(balls20[11] == "35173*"); // the paper's, reconstructed
    const std::string md = to_markdown(t);
    CHECK(contains(md, "Note: ours at 64x64"));
    CHECK(contains(md, "(512/64)²"));
    CHECK(contains(to_markdown(table3(synthetic_data(512, {"mount"}))), "≈4900*"));

    // Only V asked for: S and M columns are empty.
    PaperData only_v = synthetic_data(512);
    only_v.models = {machine::Model::V};
    CHECK(table3(only_v).rows[0][2] == "—");
    CHECK(table3(only_v).rows[0][4] != "—");
}

TEST_CASE("Table 4: M/V speed-ups and V's ILP beside the paper's ranges", "[paper]") {
    const Table t = table4(synthetic_data(512));
    REQUIRE(t.header.size() == 18);
    CHECK(t.header[2] == "OS proc M/V");
    CHECK(t.header[3] == "paper OS proc M/V");
    CHECK(t.rows[0][2] == "2.00");
    CHECK(t.rows[0][3] == "2.21–2.29");
    CHECK(t.rows[0][10] == "2.28");
    CHECK(t.rows[0][13] == "2.27–2.31"); // tetra IC ILP
    CHECK(t.rows[3][13] == "2.01–2.02"); // balls
    const Table other = table4(synthetic_data(512, {"gears"}));
    CHECK(other.rows[0][3] == "—");
}

TEST_CASE("CSV quotes cells with commas and quotes", "[paper]") {
    Table t;
    t.header = {"a", "b"};
    t.rows = {{"x,y", "say \"hi\""}};
    CHECK(to_csv(t) == "a,b\n\"x,y\",\"say \"\"hi\"\"\"\n");
}

TEST_CASE("Summary: best grid, automatic choice, crossover, M/V against the grid", "[paper]") {
    const std::string s = summary_markdown(synthetic_data(512));
    CHECK(contains(s, "| tetra | 50 | 556.0 | 50 | 50 | yes | 50 | yes |"));
    CHECK(contains(s, "| balls | 100 |"));
    CHECK(contains(s, "| 100 | 50 | no | 70 | not in the matrix |"));
    CHECK(contains(s, "agrees with the paper's best grid for 2 of 2 scenes"));
    CHECK(contains(s, "The pre-pass picks the measured best grid for 1 of 2 scenes"));
    CHECK(contains(s, "renders 100x100 through model V"));
    CHECK(contains(s, "| tetra | 100 (IC heavier at 50) | 50 (IC heavier at 20) |"));
    CHECK(contains(s, "| balls | none up to 100 (IC heavier) | 100 (IC heavier at 50) |"));
    CHECK(contains(s, "0% (roughly independent)"));
    CHECK(contains(s, "18% (roughly independent)")); // the paper's balls: 2.31 / 1.96
}

TEST_CASE("Fig. 6: an SVG panel per scene with S, M, V bars and the paper's marks", "[paper]") {
    const PaperData d = synthetic_data(64);
    const std::string svg = fig6_svg(d);
    CHECK(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0) == 0);
    CHECK(contains(svg, "</svg>\n"));
    CHECK(contains(svg, ">tetra</text>"));
    CHECK(contains(svg, ">balls</text>"));
    CHECK(contains(svg, "paper (Table 3)"));
    CHECK(contains(svg, "(512/64)² = 64"));
    // 2 scenes x 3 grids: S = 3 stacked rects, M and V = 2 rects each; + 3 legend + 1 background.
    std::size_t rects = 0;
    for (std::size_t p = 0; (p = svg.find("<rect", p)) != std::string::npos; ++p) ++rects;
    CHECK(rects == 2 * 3 * (3 + 2 + 2) + 3 + 1);
    std::size_t marks = 0;
    for (std::size_t p = 0; (p = svg.find("class=\"paper\"><title>", p)) != std::string::npos; ++p) ++marks;
    CHECK(marks == 2 * 3 * 3);
    CHECK(contains(svg, "largest stage IC"));
    CHECK_FALSE(contains(fig6_svg(synthetic_data(64, {"tetra:1"})),
                         "class=\"paper\"><title>")); // not the paper's scene
}

TEST_CASE("Reports: every file written into the output folder", "[paper]") {
    TempDir dir;
    const std::vector<std::string> files = write_reports(synthetic_data(128), (dir.path / "out").string());
    CHECK(files == std::vector<std::string>{"table2.md", "table2.csv", "table3.md", "table3.csv", "table4.md",
                                            "table4.csv", "fig6.svg", "summary.md"});
    for (const std::string& f : files) CHECK(fs::file_size(dir.path / "out" / f) > 100);
    CHECK(contains(read(dir.path / "out" / "table3.md"), "Note: ours at 128x128"));
}

TEST_CASE("The paper's own numbers as cells reproduce its speed-ups, best grids and crossovers", "[paper]") {
    const std::uint64_t mega = 1'000'000;
    PaperOptions o; // the paper's matrix: 5 scenes x 20, 50, 100 at 512x512
    std::vector<CellRecord> cells;
    for (const PublishedTimes& t : published_times()) {
        const PublishedStages& st = *find_published_stages(t.scene, t.grid);
        auto mcycles = [&](double m) { return static_cast<std::uint64_t>(m * static_cast<double>(mega)); };
        CellRecord v;
        v.key = {std::string(t.scene), t.grid, machine::Model::V, 512};
        v.total = mcycles(t.v.value);
        v.os.processing = mcycles(st.os);
        v.ic.processing = mcycles(st.ic);
        v.sc.processing = mcycles(st.sc);
        CellRecord m = v;
        m.key.model = machine::Model::M;
        m.total = mcycles(t.m.value);
        m.s_cycles = mcycles(t.s.value);
        cells.push_back(v);
        cells.push_back(m);
    }
    const PaperData d = make_data(o, std::move(cells));
    for (const auto& row : table3(d).rows) {
        INFO(row[0] << " " << row[1]);
        // ours: S/M, M/V, S/V at 5, 6, 7; the paper's at 11, 12, 13 (rounded, some reconstructed)
        for (std::size_t i = 5; i < 8; ++i) {
            // mount 20's printed S/V, 2.46, misses its own times by more than rounding: 5771 / 2329 = 2.48.
            const double margin = row[0] == "mount" && row[1] == "20" && i == 7 ? 0.021 : 0.011;
            CHECK(std::stod(row[i]) == Approx(number(row[i + 6])).margin(margin));
        }
    }
    for (const std::string& scene : o.scenes)
        CHECK(best_grid(d, scene, machine::Model::V) == (scene == "mount" || scene == "tetra" ? 50 : 100));
    const std::string s = summary_markdown(d);
    CHECK(contains(s, "agrees with the paper's best grid for 5 of 5 scenes"));
    for (const char* row : {"| balls | 100 (IC heavier at 50) | 100 (IC heavier at 50) |",
                            "| tetra | 50 (IC heavier at 20) | 50 (IC heavier at 20) |",
                            "| tree | none up to 100 (IC heavier) | none up to 100 (IC heavier) |"})
        CHECK(contains(s, row));
}
