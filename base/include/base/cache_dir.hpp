// Where nesshi keeps what it can recompute (scheduled kernels, compiled runs): one folder per kind
// under $XDG_CACHE_HOME/nesshi (when absolute), else ~/.cache/nesshi, and in it one folder per build.
//
//   base::user_cache_dir("compiled")   // "/home/me/.cache/nesshi/compiled"; "" with no HOME either
//   base::prune_cache_folders(dir, build_key);
#pragma once

#include <string>
#include <string_view>

namespace nesshi::base {

std::string user_cache_dir(std::string_view kind);
// Removes the folders in `dir` but the one named `keep` not written for 30 days: other builds'
// (errors ignored: another run may be pruning too, and a cache only saves time).
void prune_cache_folders(const std::string& dir, const std::string& keep);

} // namespace nesshi::base
