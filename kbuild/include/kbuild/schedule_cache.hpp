// Kernels scheduled for a machine other than the presets, kept on disk between runs: scheduling
// the IC's sources for a machine takes seconds (the pipeliner's solver among them), and a study
// renders many scenes on the same description. Off until a program turns it on (the command line
// does); a library user or a build tool schedules afresh.
#pragma once

#include <string>

namespace nesshi::kbuild {

// Keep scheduled kernels under `dir`/`build` (created when first written; `build` is the build's
// identity, machine::build_identity() for the front ends, so another build's schedules are never
// read, and the folders of other builds unused for 30 days are removed). An empty dir turns the
// cache off.
void enable_schedule_cache(const std::string& dir, const std::string& build);

// Where the command line keeps them: $NESSHI_CACHE_DIR (empty: off), else
// $XDG_CACHE_HOME/nesshi/kernels, else $HOME/.cache/nesshi/kernels, else off.
std::string default_schedule_cache_dir();

} // namespace nesshi::kbuild
