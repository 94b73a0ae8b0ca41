// The front ends' kernel cache (schedule_cache.hpp). A file of its own: the build identity
// (provenance.cpp) is not part of the compiled-runs generator, which compiles schedule_cache.cpp.
#include "machine/provenance.hpp"
#include "machine/schedule_cache.hpp"

namespace nesshi::machine {

void enable_default_schedule_cache() { enable_schedule_cache(default_schedule_cache_dir(), build_identity()); }

} // namespace nesshi::machine
