// The resumable cell engine: load what is stored and current, run the rest the longest first on
// threads (and, under mpirun, on the other processes too), store each cell as it finishes.
#include "paper/cell_engine.hpp"

#include "paper/paper.hpp"
#include "paper/cluster.hpp"

#include "base/progress.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "cell_transport.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

namespace nesshi::paper {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

using base::seconds_since;

int default_threads(const CellEngineOptions& o) {
    if (o.threads > 0) return o.threads;
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return std::max(1, cores / std::max(1, cluster().local_size));
}

// The shared state of one run_cells call on the process that keeps the files; every member is
// guarded by `mutex` except `next`.
struct EngineRun {
    const std::vector<Cell>& cells;
    const CellEngineOptions& options;
    CellEngineResult result;
    std::vector<std::size_t> todo;     // cell indices to run, the most work first
    std::vector<std::size_t> position; // by cell index: its place in todo
    std::vector<double> partial;       // by todo position: fraction done
    std::vector<double> weight;        // by todo position: share of the work to run
    std::size_t failed = 0;
    int threads = 1;
    Clock::time_point start = Clock::now(), last_report = start;
    std::atomic<std::size_t> next{0};
    std::mutex mutex;

    EngineRun(const std::vector<Cell>& c, const CellEngineOptions& o) : cells(c), options(o) {
        result.texts.resize(cells.size());
        position.assign(cells.size(), 0);
    }

    void load() {
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const Cell& c = cells[i];
            const bool mine = i % static_cast<std::size_t>(options.shards) == static_cast<std::size_t>(options.shard - 1);
            if (!fs::exists(c.file)) {
                if (mine) todo.push_back(i);
                continue;
            }
            std::string text = base::read_file(c.file);
            bool other = false;
            if (const auto why = stale_reasons(text, c.provenance, c.file, options.keep_other_builds ? &other : nullptr);
                !why.empty()) { // run again, whatever it holds (an older nesshi's layout, say)
                result.stale.push_back(fmt::format("{}: {}", c.name, fmt::join(why, "; ")));
                if (mine) todo.push_back(i);
                continue;
            }
            if (c.check) c.check(text); // a current cell that is malformed is an error, not a cell to run again
            result.texts[i] = std::move(text);
            ++result.loaded;
            result.other_build += other;
        }
        // The most work first, so the cell still running at the end is a short one.
        std::stable_sort(todo.begin(), todo.end(),
                         [&](std::size_t a, std::size_t b) { return cells[a].work > cells[b].work; });
        for (std::size_t k = 0; k < todo.size(); ++k) position[todo[k]] = k;
        // A cell of unknown work weighs as the mean of the known ones (1 when none is known).
        double known = 0, total = 0;
        std::size_t nknown = 0;
        for (std::size_t i : todo)
            if (cells[i].work > 0) {
                known += cells[i].work;
                ++nknown;
            }
        const double fallback = nknown ? known / static_cast<double>(nknown) : 1.0;
        for (std::size_t i : todo) {
            weight.push_back(cells[i].work > 0 ? cells[i].work : fallback);
            total += weight.back();
        }
        for (double& w : weight) w /= total;
        partial.assign(todo.size(), 0.0);
    }

    std::optional<std::size_t> take() {
        const std::size_t k = next++;
        if (k >= todo.size()) return std::nullopt;
        return todo[k];
    }

    // Called with `mutex` held.
    void report(std::size_t finished = static_cast<std::size_t>(-1), double seconds = 0, bool first = false) {
        last_report = Clock::now();
        if (!options.progress) return;
        CellEngineProgress p;
        p.cells_total = cells.size();
        p.cells_loaded = result.loaded;
        p.cells_other_build = result.other_build;
        p.cells_to_run = todo.size();
        p.cells_run = result.run;
        p.cells_failed = failed;
        double sum = 0;
        for (std::size_t k = 0; k < partial.size(); ++k) sum += partial[k] * weight[k];
        p.fraction = todo.empty() ? 1.0 : sum;
        p.elapsed_seconds = seconds_since(start);
        p.threads = threads;
        p.processes = cluster().size;
        if (first) p.stale = &result.stale;
        if (finished < cells.size()) {
            p.finished = finished;
            p.finished_text = &result.texts[finished];
            p.seconds = seconds;
        }
        options.progress(p);
    }

    // A result from this process or another: stamped, checked and written whole (a killed run
    // never leaves half a cell), then kept.
    void finish(std::size_t i, bool ok, std::string text, double seconds) {
        const Cell& c = cells[i];
        std::string failure = ok ? std::string() : std::move(text);
        if (ok) try {
                text = stamp_cell(text, c.provenance);
                if (c.check) c.check(text); // checked before it can be loaded later
                base::replace_file(c.file, text);
            } catch (const std::exception& e) {
                failure = e.what();
            }
        std::lock_guard lock(mutex);
        partial[position[i]] = 1;
        if (failure.empty()) {
            result.texts[i] = std::move(text);
            ++result.run;
        } else {
            result.failures.push_back(fmt::format("{}: {}", c.name, failure));
            ++failed;
        }
        report(i, seconds);
    }

    void run_here(std::size_t i) {
        const std::size_t k = position[i];
        CellProgressFn progress = [this, k](std::uint64_t done, std::uint64_t total) {
            std::lock_guard lock(mutex);
            partial[k] = total ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
            if (seconds_since(last_report) >= 0.25) report();
        };
        const auto t0 = Clock::now();
        try {
            std::string text = cells[i].run(progress);
            finish(i, true, std::move(text), seconds_since(t0));
        } catch (const std::exception& e) {
            finish(i, false, e.what(), seconds_since(t0));
        }
    }
};

} // namespace

CellEngineResult run_cells(const std::vector<Cell>& cells, const CellEngineOptions& o) {
    if (o.shards < 1 || o.shard < 1 || o.shard > o.shards)
        throw PaperError(fmt::format("bad shard {}/{} (1/N to N/N)", o.shard, o.shards));
    const Cluster& processes = cluster();
    if (!processes.reports()) { // an MPI worker: rank 0 keeps the files and decides what runs
        transport::work(default_threads(o), [&](std::size_t i) { return cells.at(i).run({}); });
        CellEngineResult r;
        r.texts.resize(cells.size());
        r.worker = true;
        return r;
    }
    EngineRun m(cells, o);
    const bool many = processes.size > 1;
    try {
        for (const Cell& c : cells) {
            std::error_code ec;
            fs::create_directories(fs::path(c.file).parent_path(), ec);
            if (ec) throw PaperError(base::SourceLoc(fs::path(c.file).parent_path().string()),
                                     fmt::format("cannot create: {}", ec.message()));
        }
        m.load();
    } catch (...) {
        if (many) transport::serve([] { return std::nullopt; }, [](std::size_t, bool, std::string, double) {});
        throw; // the workers were let go first, so the error ends every process
    }
    m.threads = std::clamp(default_threads(o), 1, static_cast<int>(std::max<std::size_t>(1, m.todo.size())));
    {
        std::lock_guard lock(m.mutex);
        m.report(static_cast<std::size_t>(-1), 0, true);
    }
    auto worker = [&m] {
        while (const auto i = m.take()) m.run_here(*i);
    };
    std::vector<std::thread> pool;
    // Under MPI this thread serves the other processes; alone it runs cells too.
    for (int t = many ? 0 : 1; t < m.threads; ++t) pool.emplace_back(worker);
    if (many)
        transport::serve([&m] { return m.take(); },
                         [&m](std::size_t i, bool ok, std::string text, double seconds) {
                             m.finish(i, ok, std::move(text), seconds);
                         });
    else
        worker();
    for (std::thread& t : pool) t.join();
    return std::move(m.result);
}

} // namespace nesshi::paper
