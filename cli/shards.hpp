// What `paper` and `sweep` share about spreading cells: `--shard I/N` and the progress words
// for threads and MPI processes.
#pragma once

#include "errors.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <utility>

namespace nesshi::cli {

// "I/N" with 1 <= I <= N.
inline std::pair<int, int> parse_shard(const std::string& s) {
    int i = 0, n = 0;
    char slash = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &i, &slash, &n, &extra) != 3 || slash != '/' || n < 1 || i < 1 || i > n)
        throw UsageError(fmt::format("--shard must be I/N with 1 <= I <= N (got '{}')", s));
    return {i, n};
}

inline constexpr const char* kShardHelp =
    "I/N: run only every N-th cell from the I-th (batch jobs without MPI); "
    "merge the jobs' OUT/cells folders and run once more for the whole results";

// "2 at a time", or under mpirun "2 at a time here, 3 processes".
inline std::string at_a_time(int threads, int processes) {
    if (processes <= 1) return fmt::format("{} at a time", threads);
    return fmt::format("{} at a time here, {} processes", threads, processes);
}

} // namespace nesshi::cli
