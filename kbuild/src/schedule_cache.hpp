// Internal: the on-disk store behind kbuild/schedule_cache.hpp, as the kernel build uses it.
#pragma once

#include "kbuild/kernel_build.hpp"

#include <optional>
#include <string>

namespace nesshi::kbuild::detail {

// One source scheduled for one machine: its text and build, or why it did not schedule.
struct StoredSchedule {
    std::string text, name, error;
    KernelBuild build;
};

// `key` names the sources, the kernel and the machine (schedule_key); the build is added here.
// Nothing when the cache is off, the file is missing or unreadable, or it holds another key.
std::optional<StoredSchedule> load_schedule(const std::string& key);

// Written to a temporary file and renamed, so a reader never sees half of it; a failure to write
// is silent (the cache only saves time).
void store_schedule(const std::string& key, const StoredSchedule& s);

} // namespace nesshi::kbuild::detail
