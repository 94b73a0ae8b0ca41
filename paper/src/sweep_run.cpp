// Running a sweep: each cell one machine run, stored with its provenance, loaded again when a
// resumed sweep asks for the same run; cells run concurrently, the largest images first.
#include "paper/sweep.hpp"

#include "base/read_file.hpp"
#include "base/write_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <thread>

namespace nesshi::paper {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string describe(const SweepSpec& s, const SweepCell& c) {
    std::vector<std::string> parts;
    for (std::size_t i = 0; i < s.axes.size(); ++i)
        if (s.axes[i].values.size() > 1) parts.push_back(fmt::format("{}={}", s.axes[i].name, c.values[i]));
    return parts.empty() ? std::string("the cell") : fmt::format("{}", fmt::join(parts, " "));
}

machine::Provenance provenance_of(const SweepRunInputs& in) {
    return machine::provenance(in.scene, in.grid, in.render, in.machine);
}

std::string simulate(const SweepRunInputs& in) {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene(in.scene), in.grid);
    const machine::Result r = machine::render(prep, in.render, in.machine);
    return machine::stats_json(prep, in.render, in.machine, r);
}

} // namespace

SweepRun run_sweep(const SweepSpec& s, const SweepOptions& o) {
    if (o.shards < 1 || o.shard < 1 || o.shard > o.shards)
        throw PaperError(fmt::format("bad shard {}/{} (1/N to N/N)", o.shard, o.shards));
    const std::vector<SweepCell> cells = sweep_cells(s);
    const fs::path dir = fs::path(o.out_dir) / "cells";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw PaperError(base::SourceLoc(dir.string()), fmt::format("cannot create: {}", ec.message()));

    std::vector<std::string> json(cells.size());
    std::vector<SweepRunInputs> inputs;
    std::vector<machine::Provenance> prov;
    std::vector<std::size_t> todo;
    std::vector<std::string> stale;
    SweepRun r;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        inputs.push_back(sweep_inputs(s, cells[i]));
        prov.push_back(provenance_of(inputs.back()));
        const fs::path file = dir / (cells[i].id + ".json");
        const bool mine = i % static_cast<std::size_t>(o.shards) == static_cast<std::size_t>(o.shard - 1);
        if (!fs::exists(file)) {
            if (mine) todo.push_back(i);
            continue;
        }
        std::string text = base::read_file(file.string());
        if (const auto why = stale_reasons(text, prov[i], file.string()); !why.empty()) {
            stale.push_back(fmt::format("{}: {}", describe(s, cells[i]), fmt::join(why, "; ")));
            if (mine) todo.push_back(i);
            continue;
        }
        json[i] = std::move(text);
        ++r.loaded;
    }
    // Largest images and most PEs first, so the cell still running at the end is a short one.
    std::stable_sort(todo.begin(), todo.end(), [&](std::size_t a, std::size_t b) {
        auto work = [&](std::size_t i) {
            return static_cast<double>(inputs[i].render.width) * inputs[i].render.height * inputs[i].machine.pes;
        };
        return work(a) > work(b);
    });

    std::mutex mutex;
    SweepProgress p;
    p.cells_total = cells.size();
    p.cells_loaded = r.loaded;
    p.cells_to_run = todo.size();
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    p.threads = std::clamp(o.threads > 0 ? o.threads : cores, 1, static_cast<int>(std::max<std::size_t>(1, todo.size())));
    const auto start = Clock::now();
    if (o.progress) {
        SweepProgress first = p;
        first.stale = &stale;
        o.progress(first);
    }
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t k; (k = next++) < todo.size();) {
            const std::size_t i = todo[k];
            const fs::path file = dir / (cells[i].id + ".json");
            const auto t0 = Clock::now();
            std::string text, failure;
            try {
                text = stamp_cell(simulate(inputs[i]), prov[i]);
                base::replace_file(file.string(), text);
            } catch (const std::exception& e) {
                failure = fmt::format("{}: {}", describe(s, cells[i]), e.what());
            }
            std::lock_guard lock(mutex);
            if (failure.empty()) {
                json[i] = std::move(text);
                ++r.run;
                ++p.cells_done;
            } else {
                r.failures.push_back(failure);
                ++p.cells_failed;
            }
            if (o.progress) {
                SweepProgress q = p;
                q.finished = describe(s, cells[i]);
                q.seconds = seconds_since(t0);
                q.elapsed_seconds = seconds_since(start);
                o.progress(q);
            }
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < p.threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();

    const std::string csv = sweep_csv(s, cells, json);
    r.rows_jsonl = sweep_jsonl(s, cells, json);
    std::string jsonl;
    for (const std::string& row : r.rows_jsonl) jsonl += row + "\n";
    base::replace_file((fs::path(o.out_dir) / "results.csv").string(), csv);
    base::replace_file((fs::path(o.out_dir) / "results.jsonl").string(), jsonl);
    r.files = {"results.csv", "results.jsonl"};
    if (const std::string svg = sweep_chart_svg(s, cells, json); !svg.empty()) {
        base::replace_file((fs::path(o.out_dir) / "chart.svg").string(), svg);
        r.files.push_back("chart.svg");
    }
    if (!r.failures.empty())
        throw PaperError(fmt::format("{} of {} cell(s) failed (the results hold the others):\n  {}", r.failures.size(),
                                     cells.size(), fmt::join(r.failures, "\n  ")));
    return r;
}

} // namespace nesshi::paper
