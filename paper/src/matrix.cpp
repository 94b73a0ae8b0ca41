// The resumable matrix: cells already on disk are loaded, the others run concurrently, each written
// as soon as it finishes so an interrupted run loses only the cells in flight.
#include "paper/paper.hpp"
#include "base/write_file.hpp"

#include "paper/published.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

namespace nesshi::paper {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string read_file(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    if (!f) throw PaperError(base::SourceLoc(p.string()), "cannot read");
    return s.str();
}

// The paper's time for the cell, to start the longest cells first (0 when the paper has none).
double estimated_cycles(const CellKey& k) {
    const PublishedTimes* p = find_published_times(paper_scene(k.scene), k.grid);
    if (!p) return 0;
    return k.model == machine::Model::V ? p->v.value : p->m.value;
}

// The shared state of one run_matrix call; every member is guarded by `mutex` except `next`.
struct MatrixRun {
    const PaperOptions& options;
    std::vector<CellKey> keys;
    std::vector<std::optional<CellRecord>> records; // by keys index
    std::vector<std::size_t> todo;                  // keys indices to run, longest first
    std::vector<double> partial;                    // by todo position: fraction done
    std::vector<double> weight;                     // by todo position: expected share of the work
    std::vector<std::string> failures;
    std::vector<std::string> stale;                 // stored cells run again, and why
    std::vector<machine::Provenance> provenance;    // by keys index: the current run's
    std::size_t loaded = 0, run = 0, failed = 0;
    int threads = 1;
    Clock::time_point start = Clock::now(), last_report = start;
    std::atomic<std::size_t> next{0};
    std::mutex mutex;

    explicit MatrixRun(const PaperOptions& o) : options(o), keys(matrix_cells(o)), records(keys.size()) {}

    // Called with `mutex` held.
    void report(const CellRecord* finished, bool first = false) {
        last_report = Clock::now();
        if (!options.progress) return;
        PaperProgress p;
        p.finished = finished;
        p.cells_total = keys.size();
        p.size = options.size;
        p.cells_loaded = loaded;
        p.cells_run = run;
        p.cells_failed = failed;
        p.cells_to_run = todo.size();
        double sum = 0;
        for (std::size_t i = 0; i < partial.size(); ++i) sum += partial[i] * weight[i];
        p.fraction = todo.empty() ? 1.0 : sum;
        p.elapsed_seconds = seconds_since(start);
        p.threads = threads;
        if (first) p.stale = &stale;
        options.progress(p);
    }

    void run_one(std::size_t position, const CellRunner& runner) {
        const std::size_t i = todo[position];
        const CellKey& key = keys[i];
        const fs::path file = fs::path(options.out_dir) / "cells" / cell_file_name(key);
        const auto t0 = Clock::now();
        CellProgressFn progress = [this, position](std::uint64_t done, std::uint64_t total) {
            std::lock_guard lock(mutex);
            partial[position] = total ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
            if (seconds_since(last_report) >= 0.25) report(nullptr);
        };
        try {
            const std::string text = stamp_cell(runner(key, progress), provenance[i]);
            CellRecord r = parse_cell(key, text, file.string()); // checked before it can be loaded later
            r.wall_seconds = seconds_since(t0);
            base::replace_file(file.string(), text); // a killed run never leaves half a cell
            std::lock_guard lock(mutex);
            records[i] = std::move(r);
            partial[position] = 1;
            ++run;
            report(&*records[i]);
        } catch (const std::exception& e) {
            std::lock_guard lock(mutex);
            failures.push_back(fmt::format("{}: {}", file.stem().string(), e.what()));
            partial[position] = 1;
            ++failed;
            report(nullptr);
        }
    }
};

} // namespace

MatrixResult run_matrix(const PaperOptions& o, const CellRunner& runner, const CellProvenanceFn& provenance) {
    MatrixRun m(o);
    const fs::path dir = fs::path(o.out_dir) / "cells";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw PaperError(base::SourceLoc(dir.string()), fmt::format("cannot create: {}", ec.message()));

    for (std::size_t i = 0; i < m.keys.size(); ++i) {
        m.provenance.push_back(provenance ? provenance(m.keys[i]) : machine::Provenance{});
        const fs::path file = dir / cell_file_name(m.keys[i]);
        if (!fs::exists(file)) {
            m.todo.push_back(i);
            continue;
        }
        const std::string text = read_file(file);
        CellRecord r = parse_cell(m.keys[i], text, file.string()); // a malformed file is an error
        if (const auto why = stale_reasons(text, m.provenance[i], file.string()); !why.empty()) {
            m.stale.push_back(fmt::format("{}: {}", file.stem().string(), fmt::join(why, "; ")));
            m.todo.push_back(i);
            continue;
        }
        m.records[i] = std::move(r);
        ++m.loaded;
    }
    // Longest first, so the cell still running at the end is a short one.
    std::stable_sort(m.todo.begin(), m.todo.end(), [&](std::size_t a, std::size_t b) {
        return estimated_cycles(m.keys[a]) > estimated_cycles(m.keys[b]);
    });
    m.partial.assign(m.todo.size(), 0.0);
    // Weighted by the paper's time for the cell (cells differ 100-fold); a cell the paper has no
    // time for counts as the mean of those it has (1 when it has none).
    double known = 0, total_weight = 0;
    std::size_t nknown = 0;
    for (std::size_t i : m.todo)
        if (const double c = estimated_cycles(m.keys[i]); c > 0) {
            known += c;
            ++nknown;
        }
    const double fallback = nknown ? known / static_cast<double>(nknown) : 1.0;
    for (std::size_t i : m.todo) {
        const double c = estimated_cycles(m.keys[i]);
        m.weight.push_back(c > 0 ? c : fallback);
        total_weight += m.weight.back();
    }
    for (double& w : m.weight) w /= total_weight;
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    m.threads =
        std::clamp(o.threads > 0 ? o.threads : cores, 1, static_cast<int>(std::max<std::size_t>(1, m.todo.size())));
    {
        std::lock_guard lock(m.mutex);
        m.report(nullptr, true);
    }

    auto worker = [&] {
        for (std::size_t k; (k = m.next++) < m.todo.size();) m.run_one(k, runner);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < m.threads; ++t) pool.emplace_back(worker);
    worker(); // the calling thread runs cells too
    for (std::thread& t : pool) t.join();

    MatrixResult r;
    for (auto& rec : m.records)
        if (rec) r.cells.push_back(std::move(*rec));
    r.failures = std::move(m.failures);
    r.stale = std::move(m.stale);
    r.loaded = m.loaded;
    r.run = m.run;
    return r;
}

} // namespace nesshi::paper
