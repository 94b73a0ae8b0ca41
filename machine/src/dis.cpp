// DIS, the load distributor: how pixel corners reach the PEs, and the host threads that
// simulate the PEs. Interleaved: corner k goes to PE k mod pes up front; each PE then runs to the
// end on its own host thread. Dynamic: the PEs advance in epochs of simulated time; at each
// epoch boundary DIS tops every PE up to 2 x window corners, most room first, so a PE that
// finishes its rays sooner is given more. Both are deterministic for any number of host threads:
// within an epoch the PEs do not interact.
#include "pe.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace nesshi::machine {

namespace {

int host_threads(const Options& mo) {
    const int t = mo.threads > 0 ? mo.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return std::min(t, mo.pes);
}

// fn(i) for every i < n on `threads` threads (the caller's one of them); rethrows the error of the
// lowest failing i, prefixed with the PE number when there are several.
template <class Fn>
void parallel_for(std::size_t n, int threads, Fn fn) {
    std::vector<std::string> errors(n);
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < n;) {
            try {
                fn(i);
            } catch (const std::exception& e) {
                errors[i] = n > 1 ? fmt::format("PE {}: {}", i, e.what()) : e.what();
            }
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads && static_cast<std::size_t>(t) < n; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    for (const std::string& e : errors)
        if (!e.empty()) throw std::runtime_error(e);
}

} // namespace

std::vector<PeResult> run_interleaved(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt,
                                      const Options& mo, std::size_t ncorners, CornerSink sink, int& threads) {
    std::vector<std::vector<std::uint32_t>> work(static_cast<std::size_t>(mo.pes));
    for (std::size_t k = 0; k < ncorners; ++k) work[k % work.size()].push_back(static_cast<std::uint32_t>(k));

    std::vector<PeResult> results(work.size());
    std::atomic<std::uint64_t> done{0};
    std::atomic<std::size_t> next_pe{0};
    std::mutex err_mu;
    std::string error;
    auto worker = [&] {
        for (;;) {
            const std::size_t i = next_pe.fetch_add(1);
            if (i >= work.size()) return;
            try {
                PeRun pe(setup, prep, opt, mo, std::move(work[i]), sink);
                pe.run_until(kNever, done);
                results[i] = pe.finish();
            } catch (const std::exception& e) {
                std::lock_guard lk(err_mu);
                if (error.empty()) error = work.size() > 1 ? fmt::format("PE {}: {}", i, e.what()) : e.what();
                next_pe = work.size(); // stop handing out PEs
            }
        }
    };
    threads = host_threads(mo);
    std::vector<std::thread> pool;
    std::atomic<int> finished{0};
    const int extra = mo.progress ? threads : threads - 1; // with progress, the caller only reports
    for (int t = 0; t < extra; ++t) pool.emplace_back([&] {
        worker();
        ++finished;
    });
    if (mo.progress) {
        while (finished.load() < extra) {
            mo.progress(done.load(), ncorners);
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    } else {
        worker();
    }
    for (std::thread& t : pool) t.join();
    if (!error.empty()) throw std::runtime_error(error);
    if (mo.progress) mo.progress(ncorners, ncorners);
    return results;
}

std::vector<PeResult> run_dynamic(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt,
                                  const Options& mo, std::size_t ncorners, CornerSink sink, int& threads) {
    if (mo.epoch < 1) throw std::invalid_argument("the balancing epoch must be at least 1 cycle");
    threads = host_threads(mo);
    std::vector<PeRun> pes;
    for (int i = 0; i < mo.pes; ++i) pes.emplace_back(setup, prep, opt, mo, std::vector<std::uint32_t>{}, sink);
    const std::size_t target = 2 * static_cast<std::size_t>(mo.window);
    std::atomic<std::uint64_t> done{0};
    std::size_t next = 0;
    auto last_report = std::chrono::steady_clock::now();
    for (std::uint64_t t = 0;; t += mo.epoch) {
        while (next < ncorners) { // one corner at a time to the PE with the most room
            std::size_t best = 0;
            for (std::size_t i = 1; i < pes.size(); ++i)
                if (pes[i].room(target) > pes[best].room(target)) best = i;
            if (pes[best].room(target) == 0) break;
            pes[best].give(static_cast<std::uint32_t>(next++), t);
        }
        if (next == ncorners && std::all_of(pes.begin(), pes.end(), [](const PeRun& p) { return p.done(); })) break;
        parallel_for(pes.size(), threads, [&](std::size_t i) { pes[i].run_until(t + mo.epoch, done); });
        if (mo.progress && std::chrono::steady_clock::now() - last_report > std::chrono::milliseconds(100)) {
            mo.progress(done.load(), ncorners);
            last_report = std::chrono::steady_clock::now();
        }
    }
    if (mo.progress) mo.progress(ncorners, ncorners);
    std::vector<PeResult> results;
    for (PeRun& p : pes) results.push_back(p.finish());
    return results;
}

} // namespace nesshi::machine
