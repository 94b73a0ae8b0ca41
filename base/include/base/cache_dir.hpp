// Where nesshi keeps what it can recompute (scheduled kernels, compiled runs): one folder per kind
// under $XDG_CACHE_HOME/nesshi (when absolute), else ~/.cache/nesshi, and in it one folder per build.
//
//   base::user_cache_dir("compiled")   // "/home/me/.cache/nesshi/compiled"; "" with no HOME either
//   base::prune_cache_folders(dir, build_key);
//   base::trim_cache_files(dir + "/" + build_key, ".so", 1024u << 20, just_made);
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace nesshi::base {

std::string user_cache_dir(std::string_view kind);
// Removes the folders in `dir` but the one named `keep` not written for 30 days: other builds'
// (errors ignored: another run may be pruning too, and a cache only saves time).
void prune_cache_folders(const std::string& dir, const std::string& keep);
// Removes the files of `dir` whose names end in `extension`, least recently written first, until
// they hold at most `max_bytes` together; never `keep` (a file name) nor a file `busy` says is in
// use (by its name). A reader that loads a file rewrites its time (touch_cache_file), so that the
// ones in use stay. Errors ignored, as above.
void trim_cache_files(const std::string& dir, std::string_view extension, std::uint64_t max_bytes, const std::string& keep,
                      const std::function<bool(const std::string&)>& busy = {});
void touch_cache_file(const std::string& path);

} // namespace nesshi::base
