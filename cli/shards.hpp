// What `paper` and `sweep` share about their stored cells: `--shard I/N`, `--keep-other-builds`
// and the progress words for threads, MPI processes and the stored cells run again or kept.
#pragma once

#include "errors.hpp"
#include "status.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

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

inline constexpr const char* kKeepOtherBuildsHelp =
    "keep stored cells that another build of nesshi computed (by default they run again: a new "
    "build may time the machine differently); says how many were kept";

// Which stored cells run again and why, and how many were kept from another build.
inline void report_stored(const std::vector<std::string>& stale, std::size_t other_build) {
    if (!stale.empty()) {
        status("  {} stored cell(s) run again, their provenance is not this run's:\n", stale.size());
        for (const std::string& s : stale) status("    {}\n", s);
    }
    if (other_build > 0)
        status("  {} stored cell(s) kept from another build of nesshi (--keep-other-builds)\n", other_build);
}

// "2 at a time", or under mpirun "2 at a time here, 3 processes".
inline std::string at_a_time(int threads, int processes) {
    if (processes <= 1) return fmt::format("{} at a time", threads);
    return fmt::format("{} at a time here, {} processes", threads, processes);
}

} // namespace nesshi::cli
