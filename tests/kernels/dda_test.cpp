// Differential test of the 3DDDA kernels (kernels/os/dda.s, kernels/seq/dda.s) against the
// native twin (kernels/twins/dda.hpp): the same VISITs (voxel, t_in, t_out bit for bit), the same saved
// state after each VISIT, and a MISS at the same point, on random grids and rays.
#include "support.hpp"

#include "kernels/twins/dda.hpp"

#include "iss/trace.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>

using namespace nesshi;
using namespace nesshi::kernels;
using nesshi::base::Vec3f;

namespace {

struct TestGrid {
    kernels::twins::GridGeom g;
    std::vector<std::uint8_t> occ;
};

TestGrid random_grid(std::mt19937& rng, double density) {
    std::uniform_int_distribution<int> n(1, 12);
    std::uniform_real_distribution<float> lo(-6.0f, 6.0f), cell(0.25f, 2.0f);
    std::bernoulli_distribution full(density);
    TestGrid t;
    for (int k = 0; k < 3; ++k) {
        t.g.n[k] = n(rng);
        t.g.lo[k] = lo(rng);
        t.g.cell[k] = cell(rng);
        t.g.hi[k] = t.g.lo[k] + static_cast<float>(t.g.n[k]) * t.g.cell[k];
        t.g.inv_cell[k] = 1.0f / t.g.cell[k];
    }
    t.occ.resize(static_cast<std::size_t>(t.g.n[0] * t.g.n[1] * t.g.n[2]));
    for (auto& v : t.occ) v = full(rng) ? 1 : 0;
    return t;
}

struct TestRay {
    Vec3f o, d;
    float tmin, tmax;
};

TestRay random_ray(std::mt19937& rng, const kernels::twins::GridGeom& g, int i) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto in_box = [&](float margin) {
        Vec3f p;
        for (int k = 0; k < 3; ++k) {
            const float ext = g.hi[k] - g.lo[k];
            p[k] = g.lo[k] - margin * ext + u(rng) * (1.0f + 2.0f * margin) * ext;
        }
        return p;
    };
    TestRay r;
    const int kind = i % 8;
    r.o = kind < 3 ? in_box(1.0f) : in_box(0.0f); // outside-ish, or inside the grid
    if (kind == 5) {                              // on voxel boundary planes / lattice points
        for (int k = 0; k < 3; ++k) {
            const int c = static_cast<int>(u(rng) * static_cast<float>(g.n[k] + 1));
            if (u(rng) < 0.7f) r.o[k] = g.lo[k] + static_cast<float>(c) * g.cell[k];
        }
    }
    Vec3f target = in_box(0.1f);
    Vec3f d = target - r.o;
    if (kind == 3 || kind == 6) d[static_cast<int>(u(rng) * 3.0f) % 3] = 0.0f; // parallel to a face
    if (kind == 4) {                                                         // parallel to an axis
        const int a = static_cast<int>(u(rng) * 3.0f) % 3;
        for (int k = 0; k < 3; ++k)
            if (k != a) d[k] = 0.0f;
    }
    float len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (!(len > 0.0f)) d = {0.0f, 0.0f, 1.0f}, len = 1.0f;
    r.d = abi::flush_direction(d * (1.0f / len));
    if (r.d.x == 0.0f && r.d.y == 0.0f && r.d.z == 0.0f) r.d = {1.0f, 0.0f, 0.0f};
    r.tmin = (i % 3 == 0) ? 0.0f : u(rng) * 0.5f;
    r.tmax = (i % 4 == 1) ? u(rng) * 20.0f + r.tmin : std::numeric_limits<float>::infinity();
    return r;
}

struct Visit {
    std::uint32_t voxel; // padded index
    float t_in, t_out;
    kernels::twins::DdaState s;
};

// The reference: what the OS must send for this ray, as a list of VISITs followed by a MISS.
std::vector<Visit> reference(const TestGrid& t, const TestRay& r) {
    std::vector<Visit> out;
    kernels::twins::DdaState s;
    const PaddedGrid p = padded(t.g);
    if (!kernels::twins::dda_setup(t.g, r.o, r.d, r.tmin, r.tmax, s)) return out;
    do {
        if (!t.occ[static_cast<std::size_t>(s.addr)]) continue;
        out.push_back({p.index(s.i[0], s.i[1], s.i[2]), s.t_in, s.voxel_exit(), s});
    } while (kernels::twins::dda_step(s));
    return out;
}

void run_dda(const std::string& file, const std::string& machine, iss::Engine engine, int grids, int rays_per_grid,
             std::uint32_t seed) {
    std::mt19937 rng(seed);
    long visits = 0, rays = 0;
    for (int gi = 0; gi < grids; ++gi) {
        const TestGrid t = random_grid(rng, gi % 3 == 0 ? 0.05 : (gi % 3 == 1 ? 0.3 : 0.8));
        test::Rig rig(file, machine, engine);
        rig.load(os_image(t.g, t.occ));
        rig.run();
        for (int ri = 0; ri < rays_per_grid; ++ri, ++rays) {
            const TestRay r = random_ray(rng, t.g, ri);
            const std::vector<Visit> ref = reference(t, r);
            const std::uint32_t slot = static_cast<std::uint32_t>(ri) % abi::kOsSlots;
            abi::Tag tag{slot, abi::Kind::eye, 1};
            abi::NewRay nr{tag.word(), {r.o.x, r.o.y, r.o.z}, {r.d.x, r.d.y, r.d.z}, r.tmin, r.tmax};
            rig.feed(nr.words());
            // NESSHI_TRACE_RAY=grid,ray prints a cycle trace of that ray (debugging aid)
            iss::TextTracer tracer(stderr);
            const char* tr = std::getenv("NESSHI_TRACE_RAY");
            rig.proc->set_tracer(tr && std::to_string(gi) + "," + std::to_string(ri) == tr ? &tracer : nullptr);
            INFO("grid " << gi << " n " << t.g.n[0] << "x" << t.g.n[1] << "x" << t.g.n[2] << " ray " << ri << " o "
                          << r.o.x << " " << r.o.y << " " << r.o.z << " d " << r.d.x << " " << r.d.y << " "
                          << r.d.z << " tmin " << r.tmin << " tmax " << r.tmax);
            for (std::size_t v = 0;; ++v) {
                rig.run();
                if (v == ref.size()) {
                    REQUIRE(rig.out1.size() == 0);
                    const auto w = rig.out2.drain_all();
                    REQUIRE(w.size() == 1);
                    CHECK(w[0] == tag.word());
                    break;
                }
                INFO("visit " << v << " of " << ref.size());
                REQUIRE(rig.out2.size() == 0);
                const auto w = rig.out1.drain_all();
                REQUIRE(w.size() == 12);
                const abi::Visit m = abi::Visit::from(w.data());
                const Visit& e = ref[v];
                CHECK(m.tag == (tag.word() | abi::kTagReturn));
                CHECK(m.voxel == e.voxel);
                CHECK(test::fbits(m.t_in) == test::fbits(e.t_in));
                CHECK(test::fbits(m.t_out) == test::fbits(e.t_out));
                CHECK(test::fbits(m.tmin) == test::fbits(r.tmin));
                CHECK(test::fbits(m.tmax) == test::fbits(r.tmax));
                for (int k = 0; k < 3; ++k) {
                    CHECK(test::fbits(m.o[k]) == test::fbits(r.o[k]));
                    CHECK(test::fbits(m.d[k]) == test::fbits(r.d[k]));
                }
                // the saved state: next, delta, t_exit, address and address steps
                const std::uint32_t st = abi::kOsState + slot * abi::kOsStateBytes;
                const PaddedGrid p = padded(t.g);
                for (int k = 0; k < 3; ++k) {
                    const auto kk = static_cast<std::uint32_t>(4 * k);
                    CHECK(rig.peek32(st + abi::get("ST_NEXT") + kk) == test::fbits(e.s.next[k]));
                    CHECK(rig.peek32(st + abi::get("ST_DELTA") + kk) == test::fbits(e.s.delta[k]));
                    CHECK(rig.peek32(st + abi::get("ST_ASTEP") + kk) ==
                          static_cast<std::uint32_t>(e.s.step[k]) * p.stride[k]);
                }
                CHECK(rig.peek32(st + abi::get("ST_TEXIT")) == test::fbits(e.s.t_exit));
                CHECK(rig.peek32(st + abi::get("ST_ADDR")) == abi::kOsOcc + e.voxel);
                CHECK(rig.peek32(st + abi::get("ST_TIN")) == test::fbits(e.t_in));
                ++visits;
                rig.feed(std::array<std::uint32_t, 1>{m.tag}); // RETURN: no hit in this voxel
            }
        }
    }
    WARN(machine << ": " << rays << " rays, " << visits << " visits compared");
}

} // namespace

TEST_CASE("os 3DDDA kernel matches the twin (fast engine)", "[unit][kernels][dda]") {
    run_dda("os/dda.s", "os", iss::Engine::Fast, 40, 260, 1);
}

TEST_CASE("os 3DDDA kernel matches the twin (checked engine)", "[unit][kernels][dda]") {
    run_dda("os/dda.s", "os", iss::Engine::Checked, 12, 100, 2);
}

TEST_CASE("seq 3DDDA kernel matches the twin (fast engine)", "[unit][kernels][dda]") {
    run_dda("seq/dda.s", "seq", iss::Engine::Fast, 40, 260, 3);
}

TEST_CASE("seq 3DDDA kernel matches the twin (checked engine)", "[unit][kernels][dda]") {
    run_dda("seq/dda.s", "seq", iss::Engine::Checked, 12, 100, 4);
}

TEST_CASE("os 3DDDA kernel on os-real (the voxel loop pipelined for it) matches the twin", "[unit][kernels][dda]") {
    run_dda("os/dda.s", "os-real", iss::Engine::Fast, 40, 260, 5);
    run_dda("os/dda.s", "os-real", iss::Engine::Checked, 12, 100, 6);
}
