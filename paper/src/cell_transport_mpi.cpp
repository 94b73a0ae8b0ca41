// Cells over MPI, pulled: a worker rank asks rank 0 for a cell whenever one of its threads is
// free, and rank 0 answers from its longest-first list, so fast and slow hosts stay busy alike.
// Every wait polls with a short sleep: OpenMPI's blocking calls spin, which on a small host
// steals a core from the cells.
#include "cell_transport.hpp"

#include "base/progress.hpp"

#include <mpi.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace nesshi::paper::transport {

namespace {

enum Tag : int {
    kRequest = 1, // worker -> 0, empty: a thread of mine is free
    kJob = 2,     // 0 -> worker, one int64: the cell index, or -1: no more cells
    kResult = 3,  // worker -> 0: ResultHeader, then the text (or the failure message)
    kDone = 4,    // worker -> 0, empty: all my cells are back
};

struct ResultHeader {
    std::uint64_t index;
    double seconds;
    std::uint8_t ok;
};

MPI_Status wait_for(int source, int tag) {
    MPI_Status st;
    for (int flag = 0;;) {
        MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &st);
        if (flag) return st;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

std::vector<char> receive_bytes(const MPI_Status& st) {
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::vector<char> buf(static_cast<std::size_t>(n));
    MPI_Recv(buf.data(), n, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return buf;
}

struct Outcome {
    std::size_t index;
    bool ok;
    std::string text;
    double seconds;
};

void send_result(const Outcome& r) {
    const ResultHeader h{r.index, r.seconds, static_cast<std::uint8_t>(r.ok)};
    std::vector<char> buf(sizeof h + r.text.size());
    std::memcpy(buf.data(), &h, sizeof h);
    std::memcpy(buf.data() + sizeof h, r.text.data(), r.text.size());
    MPI_Send(buf.data(), static_cast<int>(buf.size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
}

} // namespace

void serve(const std::function<std::optional<std::size_t>()>& take,
           const std::function<void(std::size_t, bool, std::string, double)>& finish) {
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    for (int working = size - 1; working > 0;) {
        const MPI_Status st = wait_for(MPI_ANY_SOURCE, MPI_ANY_TAG);
        std::vector<char> msg = receive_bytes(st);
        if (st.MPI_TAG == kRequest) {
            const std::optional<std::size_t> i = take();
            const std::int64_t job = i ? static_cast<std::int64_t>(*i) : -1;
            MPI_Send(&job, 1, MPI_INT64_T, st.MPI_SOURCE, kJob, MPI_COMM_WORLD);
        } else if (st.MPI_TAG == kResult && msg.size() >= sizeof(ResultHeader)) {
            ResultHeader h;
            std::memcpy(&h, msg.data(), sizeof h);
            finish(static_cast<std::size_t>(h.index), h.ok != 0, std::string(msg.begin() + sizeof h, msg.end()), h.seconds);
        } else if (st.MPI_TAG == kDone) {
            --working;
        }
    }
}

void work(int threads, const std::function<std::string(std::size_t)>& run) {
    std::mutex mutex;
    std::condition_variable changed;
    std::deque<std::size_t> jobs;
    std::deque<Outcome> outcomes;
    bool closing = false;
    auto runner = [&] {
        for (;;) {
            std::unique_lock lock(mutex);
            changed.wait(lock, [&] { return closing || !jobs.empty(); });
            if (jobs.empty()) return;
            const std::size_t i = jobs.front();
            jobs.pop_front();
            lock.unlock();
            const auto t0 = std::chrono::steady_clock::now();
            Outcome r{i, true, {}, 0};
            try {
                r.text = run(i);
            } catch (const std::exception& e) {
                r.ok = false;
                r.text = e.what();
            }
            r.seconds = base::seconds_since(t0);
            lock.lock();
            outcomes.push_back(std::move(r));
            changed.notify_all();
        }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(runner);
    // This thread alone talks to rank 0 (MPI_THREAD_FUNNELED).
    for (int in_flight = 0, stopped = 0;;) {
        while (!stopped && in_flight < threads) {
            MPI_Send(nullptr, 0, MPI_BYTE, 0, kRequest, MPI_COMM_WORLD);
            wait_for(0, kJob);
            std::int64_t job = -1;
            MPI_Recv(&job, 1, MPI_INT64_T, 0, kJob, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (job < 0) {
                stopped = 1;
                break;
            }
            std::lock_guard lock(mutex);
            jobs.push_back(static_cast<std::size_t>(job));
            ++in_flight;
            changed.notify_all();
        }
        if (in_flight == 0) break;
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return !outcomes.empty(); });
        Outcome r = std::move(outcomes.front());
        outcomes.pop_front();
        lock.unlock();
        send_result(r);
        --in_flight;
    }
    {
        std::lock_guard lock(mutex);
        closing = true;
        changed.notify_all();
    }
    for (std::thread& t : pool) t.join();
    MPI_Send(nullptr, 0, MPI_BYTE, 0, kDone, MPI_COMM_WORLD);
}

} // namespace nesshi::paper::transport
