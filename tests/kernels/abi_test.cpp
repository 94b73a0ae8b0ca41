// kernels/abi.inc must be exactly the text generated from kernels/abi.hpp, so the assembly and
// C++ sides of the ABI cannot drift; the failure message carries the text to paste.
#include "support.hpp"

#include <fstream>
#include <sstream>

using namespace nesshi::kernels;

TEST_CASE("abi.inc is generated from abi.hpp", "[unit][kernels][abi]") {
    std::ifstream f(test::kernel_path("abi.inc"));
    REQUIRE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string want = abi::inc_text();
    INFO("kernels/abi.inc is stale; replace it with:\n" << want);
    CHECK(ss.str() == want);
}

TEST_CASE("abi constants are consistent", "[unit][kernels][abi]") {
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).slot == 77);
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).kind == abi::Kind::shadow);
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).depth == 3);
    CHECK((abi::Tag{65535, abi::Kind::refract, 63}.word() & abi::kTagReturn) == 0);
    CHECK(abi::get("MSG_VISIT") == 12);
    CHECK(abi::get("NO_SUCH_NAME") == -1);
}

TEST_CASE("the padded occupancy map frames the grid with OCC_BORDER", "[unit][kernels][abi]") {
    nesshi::rt::twins::GridGeom g;
    g.n[0] = 3, g.n[1] = 2, g.n[2] = 1;
    std::vector<std::uint8_t> occ(6, 0);
    occ[4] = 1; // (1, 1, 0)
    const MemImage m = os_image(g, occ);
    const PaddedGrid p = padded(g);
    CHECK(p.voxels() == 5 * 4 * 3);
    CHECK(m.bytes[abi::kOsOcc + p.index(1, 1, 0)] == abi::kOccFull);
    CHECK(m.bytes[abi::kOsOcc + p.index(0, 0, 0)] == abi::kOccEmpty);
    CHECK(m.bytes[abi::kOsOcc + p.index(-1, 0, 0)] == abi::kOccBorder);
    CHECK(m.bytes[abi::kOsOcc + p.index(3, 1, 0)] == abi::kOccBorder);
    CHECK(m.bytes[abi::kOsOcc + p.index(0, 0, 1)] == abi::kOccBorder);
}
