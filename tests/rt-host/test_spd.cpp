// SPD generators against the reference NFF files: same entities in order, numbers within 1e-5 relative.
#include "support.hpp"

#include "rt/spd.hpp"

using namespace nesshi::rt;
using namespace nesshi::rt::test;

TEST_CASE("SPD names", "[spd]") {
    CHECK(parse_spd_name("balls")->size == 0);
    CHECK(parse_spd_name("tree:3")->size == 3);
    CHECK_FALSE(parse_spd_name("foo.nff"));
    CHECK_THROWS(parse_spd_name("balls:zero"));
    CHECK_THROWS(generate_spd("nope", 1));
}
