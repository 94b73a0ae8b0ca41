// Traversal + grid against brute force: the same nearest hit (shape and t, bit for bit) on random rays.
#include "support.hpp"

#include "rt/trace.hpp"

#include <cstring>

using namespace nesshi::rt;
using namespace nesshi::rt::test;

namespace {

void compare_scene(const Scene& sc, int n, int rays, std::uint32_t seed) {
    ShapeSet set = build_shapes(sc);
    Grid g = build_grid(sc, set, n);
    Box box = scene_bounds(sc);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    TraceCounters cg, cb;
    int hits = 0, mismatches = 0, shadow_mismatches = 0;
    for (int i = 0; i < rays; ++i) {
        Ray r;
        // Half the rays start inside the scene's box, half outside it (in a box three times as large).
        r.o = random_in(rng, box, i % 2 ? 0.0 : 1.0);
        if (i % 4 == 3) {
            // Aim at a random shape's bounds to get many hits.
            const Box& b = set.bounds[rng() % set.bounds.size()];
            r.d = normalize(random_in(rng, b, 0.0) - r.o);
            if (!(dot(r.d, r.d) > 0.5f)) r.d = random_unit(rng);
        } else {
            r.d = random_unit(rng);
        }
        r.tmin = i % 3 == 0 ? 0.0f : kSecondaryEpsilon;
        Hit a = nearest_hit(g, set, r, cg);
        Hit b = nearest_hit_brute(set, r, cb);
        if (a.hit) ++hits;
        bool same = a.hit == b.hit && (!a.hit || (a.shape == b.shape && std::memcmp(&a.t, &b.t, sizeof(float)) == 0));
        if (!same && ++mismatches <= 5)
            UNSCOPED_INFO("ray " << i << " o " << r.o.x << " " << r.o.y << " " << r.o.z << " d " << r.d.x << " " << r.d.y
                                 << " " << r.d.z << ": grid " << a.hit << " " << a.shape << " t " << a.t << ", brute "
                                 << b.hit << " " << b.shape << " t " << b.t);
        // Shadow-ray form: any hit before a random tmax.
        r.tmax = u01(rng) * 2.0f * static_cast<float>(length(box.hi - box.lo));
        if (any_hit(g, set, r, cg) != any_hit_brute(set, r, cb)) ++shadow_mismatches;
    }
    CHECK(mismatches == 0);
    CHECK(shadow_mismatches == 0);
    CHECK(hits > rays / 20);
    // The grid must save work against brute force.
    CHECK(cg.triangle_tests + cg.quadric_tests < cb.triangle_tests + cb.quadric_tests);
}

} // namespace

TEST_CASE("Grid nearest hit equals brute force on random rays", "[trace]") {
    NESSHI_REQUIRE_SHARED();
    const int rays = scaled(100000);
    std::uint32_t seed = 100;
    for (const std::string& f : small_scenes()) {
        Scene sc = load_nff_file(shared_spd(f));
        for (int n : {13, 50}) {
            INFO(f << " grid " << n << ", " << rays << " rays");
            compare_scene(sc, n, n == 50 ? rays : rays / 4, seed++);
        }
    }
}

TEST_CASE("Grid nearest hit equals brute force on axis-parallel and eye rays", "[trace]") {
    NESSHI_REQUIRE_SHARED();
    for (const std::string& f : {std::string("tetra-s3.nff"), std::string("rings-s1.nff")}) {
        Scene sc = load_nff_file(shared_spd(f));
        ShapeSet set = build_shapes(sc);
        Grid g = build_grid(sc, set, 10);
        Box box = scene_bounds(sc);
        std::mt19937 rng(9);
        TraceCounters c;
        for (int i = 0; i < scaled(20000); ++i) {
            Ray r;
            r.o = random_in(rng, box, 0.3);
            r.d = Vec3f{0, 0, 0};
            r.d[i % 3] = (i / 3) % 2 ? 1.0f : -1.0f;
            // Also on voxel boundaries: snap the origin to a grid plane.
            if (i % 5 == 0) {
                int k = (i / 5) % 3;
                r.o[k] = g.geom.lo[k] + static_cast<float>(rng() % 11) * g.geom.cell[k];
            }
            Hit a = nearest_hit(g, set, r, c), b = nearest_hit_brute(set, r, c);
            REQUIRE(a.hit == b.hit);
            if (a.hit) {
                REQUIRE(a.shape == b.shape);
                REQUIRE(a.t == b.t);
            }
        }
    }
}

TEST_CASE("Ray and hit records format with fmt", "[trace]") {
    Ray r;
    r.o = {1, 2, 3};
    r.d = {0, 0, 1};
    CHECK(fmt::format("{}", r) == "eye ray depth 1 o (1 2 3) d (0 0 1) t (0, inf)");
    Hit h;
    CHECK(fmt::format("{}", h) == "miss");
    h.hit = true;
    h.entity = 4;
    h.shape = 7;
    h.t = 2.5f;
    CHECK(fmt::format("{}", h) == "hit primitive 4 (shape 7) t 2.5");
}

// The paper prices a quadric test at 50 cycles only when its quadratic has two distinct real roots,
// so the counters keep those tests apart: a ray through a sphere, one beside it, and one behind.
TEST_CASE("Quadric tests with two distinct real roots are counted apart", "[trace]") {
    const Scene sc = parse_nff("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n"
                               "f 1 0 0 1 0 0 0 0\ns 0 0 0 1\n",
                               "two_roots.nff");
    ShapeSet set = build_shapes(sc);
    Grid g = build_grid(sc, set, 4);
    TraceCounters c;
    Ray through;
    through.o = {0, 0, 5};
    through.d = {0, 0, -1};
    CHECK(nearest_hit(g, set, through, c).hit);
    CHECK(c.quadric_tests >= 1);
    CHECK(c.quadric_two_roots == c.quadric_tests); // every voxel on its way lists the sphere, every test has both roots
    TraceCounters beside;
    Ray past = through;
    past.o = {0.99f, 0.99f, 5}; // inside the sphere's box, outside the sphere: tested, no real root
    CHECK_FALSE(nearest_hit(g, set, past, beside).hit);
    CHECK(beside.quadric_tests >= 1);
    CHECK(beside.quadric_two_roots == 0);
    TraceCounters behind;
    Ray away = through;
    away.o = {0, 0, -0.5f}; // starts inside, the front root behind it: a miss with two real roots
    away.d = {0, 0, -1};
    away.tmin = 0.1f; // the front root at t = -1.5 is behind, the back one (t = 0.5) does not count: one-sided
    CHECK_FALSE(nearest_hit(g, set, away, behind).hit);
    CHECK(behind.quadric_two_roots == behind.quadric_tests);
    CHECK(behind.quadric_tests >= 1);
    TraceCounters sum = c;
    sum += beside;
    CHECK(sum.quadric_two_roots == c.quadric_two_roots);
}
