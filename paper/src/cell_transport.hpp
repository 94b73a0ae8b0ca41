// How the cell engine spreads cells over the processes of an MPI run (cell_transport_mpi.cpp;
// cell_transport_none.cpp in a build without MPI, where the cluster is always one process).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace nesshi::paper::transport {

// Rank 0: answers the other ranks' requests with cell indices from `take` until it returns
// nullopt, hands each result to `finish` (ok, the text or the failure message, the cell's host
// seconds), and returns when
// every rank has finished. Its own cells run on other threads meanwhile; `finish` is thread-safe.
void serve(const std::function<std::optional<std::size_t>()>& take,
           const std::function<void(std::size_t, bool, std::string, double)>& finish);

// Other ranks: asks rank 0 for cells, runs each with `run` (which throws on failure), `threads`
// at a time, sends back each result, and returns when rank 0 has no more.
void work(int threads, const std::function<std::string(std::size_t)>& run);

} // namespace nesshi::paper::transport
