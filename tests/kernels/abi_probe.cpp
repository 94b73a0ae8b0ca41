// Not built with the tests: CTest compiles it twice, with a known ABI name (it must compile) and
// with a typo (it must not), so abi::get's compile-time lookup stays a build error for typos.
#include "kernels/abi.hpp"

#define NESSHI_STR2(x) #x
#define NESSHI_STR(x) NESSHI_STR2(x)
static_assert(nesshi::kernels::abi::get(NESSHI_STR(NESSHI_ABI_NAME)) >= 0);
