// The cell engine with stand-in cells: order, shards, resumption, failures, refused files, progress.
#include "paper/cell_engine.hpp"
#include "paper/paper.hpp"

#include "common/temp_dir.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <mutex>
#include <stdexcept>

using namespace nesshi;
using namespace nesshi::paper;
namespace fs = std::filesystem;
using nesshi::test::TempDir;

namespace {

// Cells 0..n-1 whose work grows with the index; each records that it ran. Cell `failing` throws.
struct StandIn {
    std::mutex mutex;
    std::vector<std::size_t> ran;

    std::vector<Cell> cells(const TempDir& dir, std::size_t n, std::size_t failing = static_cast<std::size_t>(-1)) {
        std::vector<Cell> out;
        for (std::size_t i = 0; i < n; ++i) {
            Cell c;
            c.name = fmt::format("cell{}", i);
            c.file = (dir.path / "cells" / (c.name + ".json")).string();
            c.provenance = {{"options.index", std::to_string(i)}};
            c.work = static_cast<double>(i + 1);
            c.run = [this, i, failing](const CellProgressFn& progress) {
                if (progress) progress(1, 2);
                {
                    std::lock_guard lock(mutex);
                    ran.push_back(i);
                }
                if (i == failing) throw std::runtime_error("no such machine");
                return fmt::format(R"({{"cycles": {{"total": {}}}}})", 100 + i);
            };
            out.push_back(std::move(c));
        }
        return out;
    }
};

CellEngineOptions options(int threads, int shard = 1, int shards = 1) {
    CellEngineOptions o;
    o.threads = threads;
    o.shard = shard;
    o.shards = shards;
    return o;
}

} // namespace

TEST_CASE("cell engine: runs every cell once, the most work first, and stores each") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    const std::vector<Cell> cells = s.cells(dir, 5);
    const CellEngineResult r = run_cells(cells, options(1));
    CHECK(s.ran == std::vector<std::size_t>{4, 3, 2, 1, 0});
    CHECK(r.run == 5);
    CHECK(r.loaded == 0);
    CHECK_FALSE(r.worker);
    for (std::size_t i = 0; i < cells.size(); ++i) {
        CHECK(fs::exists(cells[i].file));
        CHECK(r.texts[i].find(fmt::format("\"total\": {}", 100 + i)) != std::string::npos);
        CHECK(stale_reasons(r.texts[i], cells[i].provenance, cells[i].file).empty()); // stamped
    }
}

TEST_CASE("cell engine: two shards share the cells, and the second loads the first's") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    const std::vector<Cell> cells = s.cells(dir, 5);
    const CellEngineResult first = run_cells(cells, options(2, 1, 2));
    CHECK(first.run == 3); // cells 0, 2, 4
    for (std::size_t i = 0; i < cells.size(); ++i) CHECK(first.texts[i].empty() == (i % 2 == 1));
    const CellEngineResult second = run_cells(cells, options(2, 2, 2));
    CHECK(second.loaded == 3);
    CHECK(second.run == 2);
    for (const std::string& t : second.texts) CHECK_FALSE(t.empty());
    CHECK(s.ran.size() == 5);
    CHECK_THROWS_WITH(run_cells(cells, options(0, 3, 2)), Catch::Contains("bad shard 3/2"));
}

TEST_CASE("cell engine: a stored cell whose provenance changed runs again, saying why") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    std::vector<Cell> cells = s.cells(dir, 3);
    run_cells(cells, {});
    cells[1].provenance["options.index"] = "one";
    const CellEngineResult r = run_cells(cells, {});
    CHECK(r.loaded == 2);
    CHECK(r.run == 1);
    REQUIRE(r.stale.size() == 1);
    CHECK(r.stale[0].rfind("cell1: options.index", 0) == 0);
}

TEST_CASE("cell engine: cells of another build run again, or are kept and counted when asked") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    std::vector<Cell> cells = s.cells(dir, 3);
    for (Cell& c : cells) c.provenance["build"] = "old";
    run_cells(cells, {});
    for (Cell& c : cells) c.provenance["build"] = "new";
    cells[2].provenance["options.index"] = "two"; // differs in more than its build
    CellEngineOptions keep;
    keep.keep_other_builds = true;
    const CellEngineResult kept = run_cells(cells, keep);
    CHECK(kept.loaded == 2);
    CHECK(kept.other_build == 2);
    CHECK(kept.run == 1);
    REQUIRE(kept.stale.size() == 1);
    CHECK(kept.stale[0] == "cell2: options.index: 2 -> two"); // the build is not a reason when kept
    const CellEngineResult rerun = run_cells(cells, {});
    CHECK(rerun.loaded == 1); // cell 2, stored by the run above with this build
    CHECK(rerun.other_build == 0);
    CHECK(rerun.run == 2);
    REQUIRE(rerun.stale.size() == 2);
    CHECK(rerun.stale[0] == "cell0: build: old -> new");
}

TEST_CASE("cell engine: a failing cell is reported and the others still run") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    const std::vector<Cell> cells = s.cells(dir, 4, 2);
    const CellEngineResult r = run_cells(cells, options(2));
    CHECK(r.run == 3);
    CHECK(r.failures == std::vector<std::string>{"cell2: no such machine"});
    CHECK(r.texts[2].empty());
    CHECK_FALSE(fs::exists(cells[2].file));
}

TEST_CASE("cell engine: a stored file its check refuses is an error naming it") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    std::vector<Cell> cells = s.cells(dir, 2);
    dir.file("cells/cell0.json", stamp_cell("{}", cells[0].provenance)); // current, but holds no result
    cells[0].check = [f = cells[0].file](const std::string& text) {
        if (!nlohmann::json::parse(text).contains("cycles")) throw PaperError(base::SourceLoc(f), "malformed cell file");
    };
    CHECK_THROWS_WITH(run_cells(cells, {}), Catch::Contains("cell0.json: error: malformed cell file"));
    CHECK(s.ran.empty()); // nothing ran before the stored cells were all read
}

TEST_CASE("cell engine: progress names each finished cell and ends at the whole") {
    TempDir dir("nesshi-cell-engine");
    StandIn s;
    const std::vector<Cell> cells = s.cells(dir, 3);
    std::vector<std::size_t> finished;
    double last_fraction = -1;
    bool started = false;
    CellEngineOptions o;
    o.threads = 1;
    o.progress = [&](const CellEngineProgress& p) {
        if (p.stale) started = true;
        if (p.finished < cells.size()) {
            finished.push_back(p.finished);
            CHECK_FALSE(p.finished_text->empty());
        }
        CHECK(p.fraction >= last_fraction);
        last_fraction = p.fraction;
    };
    run_cells(cells, o);
    CHECK(started);
    CHECK(finished == std::vector<std::size_t>{2, 1, 0});
    CHECK(last_fraction == Approx(1.0));
}
