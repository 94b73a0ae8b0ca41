// Each test case runs in a process of its own (catch_discover_tests), and a render on the `ic`
// preset schedules the IC's per-kind loops for it to weigh them (about 5 CPU-seconds, most of it
// in z3): the suite keeps scheduled kernels in the build tree, as the command line keeps them in
// the user's cache (machine/schedule_cache.hpp), so that only the first case pays. The cache
// only saves time: a kernel is the same scheduled or loaded.
#include "machine/provenance.hpp"
#include "machine/schedule_cache.hpp"

namespace {
[[maybe_unused]] const bool kCacheOn = [] {
    nesshi::machine::enable_schedule_cache(NESSHI_TEST_SCHEDULE_CACHE, nesshi::machine::build_identity());
    return true;
}();
} // namespace
