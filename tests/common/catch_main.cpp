// The one Catch2 main of every test suite (library nesshi_catch_main): Catch2 v2's
// implementation is compiled here once, not once per suite (about 30 s of compilation each).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
