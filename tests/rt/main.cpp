// Catch2 main for the nesshi_rt tests.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
