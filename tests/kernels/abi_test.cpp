// kernels/abi.inc must be exactly the text generated from kernels/abi.hpp, so the assembly and
// C++ sides of the ABI cannot drift; the failure message carries the text to paste. The ABI's
// memory limits must be the machine descriptions' memories, which are their one source.
#include "support.hpp"

#include "kernels/messages.hpp"
#include "kernels/sources.hpp"

using namespace nesshi;
using namespace nesshi::kernels;

TEST_CASE("abi.inc is generated from abi.hpp", "[unit][kernels][abi]") {
    const std::string want = abi::inc_text();
    INFO("kernels/abi.inc is stale; replace it with:\n" << want);
    CHECK(embedded().text("abi.inc") == want);
}

namespace {
const isa::MemoryDesc& region(const isa::Machine& m, const std::string& name) {
    for (const isa::MemoryDesc& r : m.memories)
        if (r.name == name) return r;
    FAIL("machine " << m.name << " has no memory '" << name << "'");
    throw;
}
} // namespace

TEST_CASE("the ABI's memory limits are the presets' [[memory]] regions", "[unit][kernels][abi]") {
    for (const char* os : {"os", "os-real", "seq", "seq-real"}) {
        INFO(os);
        const isa::Machine m = isa::load_machine(os);
        const isa::MemoryDesc& sram = region(m, "sram");
        CHECK(sram.base == abi::get("OS_GEOM"));
        CHECK(std::uint64_t{sram.base} + sram.size == abi::get("OS_OCC_LIMIT"));
    }
    for (const char* ic : {"ic", "ic-real", "seq", "seq-real"}) {
        INFO(ic);
        const isa::Machine m = isa::load_machine(ic);
        const isa::MemoryDesc& res = region(m, "resident");
        CHECK(res.base == abi::get("IC_HEADER"));
        CHECK(std::uint64_t{res.base} + res.size == abi::get("IC_RESIDENT_LIMIT"));
        CHECK(region(m, "global").base == abi::get("IC_GLOBAL"));
        CHECK(region(m, "global").cached);
    }
}

TEST_CASE("abi constants are consistent", "[unit][kernels][abi]") {
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).slot == 77);
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).kind == abi::Kind::shadow);
    CHECK(abi::Tag::from(abi::Tag{77, abi::Kind::shadow, 3}.word()).depth == 3);
    CHECK((abi::Tag{65535, abi::Kind::refract, 63}.word() & abi::kTagReturn) == 0);
    static_assert(abi::get("MSG_VISIT") == 12); // an unknown name does not build: abi_probe.cpp
}

TEST_CASE("the padded occupancy map frames the grid with OCC_BORDER", "[unit][kernels][abi]") {
    nesshi::kernels::twins::GridGeom g;
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
