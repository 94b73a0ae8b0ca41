// Property tests of the intersection and traversal twins: hits on the surface, one-sidedness, DDA walk.
#include "support.hpp"

#include "kernels/twins/dda.hpp"
#include "kernels/twins/quadric.hpp"
#include "kernels/twins/triangle.hpp"

#include <cmath>

using namespace nesshi;
using namespace nesshi::rt;
using nesshi::rt::test::random_unit;
using nesshi::rt::test::scaled;

namespace {

Scene one(const std::string& body, double t = 0) {
    std::string text = "f 1 1 1 1 0.5 10 " + std::to_string(t) + " 1.5\n" + body;
    return parse_nff(text, "twin.nff");
}

// Q of the record at a world point, in double (the reference for "hit lies on the surface").
double quadric_value(const Shape& s, Vec3d p) {
    const auto& w = s.w;
    Vec3d q = p - Vec3d{w[0], w[1], w[2]};
    return w[3] * q.x * q.x + w[4] * q.y * q.y + w[5] * q.z * q.z + 2 * w[6] * q.x * q.y + 2 * w[7] * q.y * q.z +
           2 * w[8] * q.z * q.x + 2 * w[9] * q.x + 2 * w[10] * q.y + 2 * w[11] * q.z + w[12];
}

} // namespace

TEST_CASE("Sphere twin: hits lie on the sphere, opaque spheres are one-sided", "[twins]") {
    Scene sc = one("s 0.5 -0.25 1 0.75\n");
    ShapeSet set = build_shapes(sc);
    REQUIRE(set.shapes.size() == 1);
    const Shape& s = set.shapes[0];
    std::mt19937 rng(1);
    int hits = 0;
    for (int i = 0; i < scaled(20000); ++i) {
        // From outside, aimed at a random point of the ball: must hit the front, on the surface.
        Vec3f target = Vec3f{0.5f, -0.25f, 1.0f} + random_unit(rng) * 0.7f;
        Vec3f o = Vec3f{0.5f, -0.25f, 1.0f} + random_unit(rng) * 3.0f;
        Vec3f d = normalize(target - o);
        auto h = kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), o, d, 0.0f);
        REQUIRE(h.hit);
        CHECK(h.front);
        Vec3d p = to_double(o) + to_double(d) * static_cast<double>(h.t);
        CHECK(std::abs(length(p - Vec3d{0.5, -0.25, 1}) - 0.75) < 5e-6);
        ++hits;
        // From inside: an opaque sphere is invisible (SPD rule 2).
        Vec3f inside = Vec3f{0.5f, -0.25f, 1.0f} + random_unit(rng) * 0.5f;
        CHECK_FALSE(kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), inside, random_unit(rng), 0.0f).hit);
        // Pointing away from the sphere: no hit.
        CHECK_FALSE(kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), o, -d, 0.0f).hit);
    }
    CHECK(hits > 0);
}

TEST_CASE("Sphere twin: transmitting spheres are two-sided, negative radius shows the inside", "[twins]") {
    ShapeSet glass = build_shapes(one("s 0 0 0 1\n", 0.9));
    ShapeSet inner = build_shapes(one("s 0 0 0 -1\n"));
    std::mt19937 rng(2);
    for (int i = 0; i < scaled(5000); ++i) {
        Vec3f o = random_unit(rng) * 0.5f, d = random_unit(rng);
        auto g = kernels::twins::intersect_quadric(glass.shapes[0].w.data(), glass.shapes[0].two_sided(), o, d, 0.0f);
        auto n = kernels::twins::intersect_quadric(inner.shapes[0].w.data(), inner.shapes[0].two_sided(), o, d, 0.0f);
        REQUIRE(g.hit);
        CHECK_FALSE(g.front);
        REQUIRE(n.hit);
        CHECK(n.front); // the inside is the visible side of a negative-radius sphere
        CHECK(std::abs(length(to_double(o + d * n.t)) - 1.0) < 2e-6);
        Vec3f out = random_unit(rng) * 3.0f;
        auto far = kernels::twins::intersect_quadric(inner.shapes[0].w.data(), false, out, normalize(-out), 0.0f);
        REQUIRE(far.hit); // from outside, the ray passes the near side and sees the far inside
        CHECK(far.t == Approx(4.0).epsilon(1e-5));
    }
}

TEST_CASE("Cylinder and cone twins: hits on the surface within the axial range, outside only", "[twins]") {
    ShapeSet set = build_shapes(one("c 1 2 3 0.5 2 2.5 4.5 0.5\nc -1 0 0 0.8 -1 0 2 0.2\n"));
    REQUIRE(set.shapes.size() == 2);
    std::mt19937 rng(3);
    const Scene src = parse_nff("c 1 2 3 0.5 2 2.5 4.5 0.5\nc -1 0 0 0.8 -1 0 2 0.2\n", "x");
    for (std::size_t si = 0; si < 2; ++si) {
        const Shape& s = set.shapes[si];
        const Entity& e = src.entities[si];
        Vec3d axis = normalize(e.apex - e.base);
        double len = length(e.apex - e.base);
        int hits = 0;
        for (int i = 0; i < scaled(20000); ++i) {
            Vec3f o = to_float(e.base + (e.apex - e.base) * 0.5) + random_unit(rng) * 4.0f;
            Vec3f d = random_unit(rng);
            auto h = kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), o, d, 0.0f);
            if (!h.hit) continue;
            ++hits;
            CHECK(h.front);
            Vec3d p = to_double(o) + to_double(d) * static_cast<double>(h.t);
            double ax = dot(p - e.base, axis);
            CHECK(ax >= -1e-5);
            CHECK(ax <= len + 1e-5);
            double radial = length((p - e.base) - axis * ax);
            double r = e.base_r + (e.apex_r - e.base_r) * ax / len;
            CHECK(std::abs(radial - r) < 1e-5);
            CHECK(std::abs(quadric_value(s, p)) < 1e-5);
            // The outward normal (gradient of Q) faces the ray: the hit is on the outside.
            const auto& w = s.w;
            Vec3d q = p - Vec3d{w[0], w[1], w[2]};
            Vec3d grad{w[3] * q.x + w[6] * q.y + w[8] * q.z + w[9], w[6] * q.x + w[4] * q.y + w[7] * q.z + w[10],
                       w[8] * q.x + w[7] * q.y + w[5] * q.z + w[11]};
            CHECK(dot(grad, to_double(d)) < 1e-6);
        }
        CHECK(hits > scaled(20000) / 400);
    }
}

TEST_CASE("Triangle twin: hits inside and on the plane, back faces pass unless two-sided", "[twins]") {
    ShapeSet one_sided = build_shapes(one("p 3\n0 0 0\n2 0 0\n0 1 1\n"));
    ShapeSet two_sided = build_shapes(one("p 3\n0 0 0\n2 0 0\n0 1 1\n", 0.5));
    const Shape& s = one_sided.shapes[0];
    const Vec3d v0{0, 0, 0}, v1{2, 0, 0}, v2{0, 1, 1};
    const Vec3d n = cross(v1 - v0, v2 - v0);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < scaled(20000); ++i) {
        double a = u(rng), b = u(rng);
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        Vec3d target = v0 + (v1 - v0) * a + (v2 - v0) * b;
        Vec3f o = to_float(target + normalize(n) * 2.0) + random_unit(rng) * 0.5f; // front side
        Vec3f d = normalize(to_float(target) - o);
        auto h = kernels::twins::intersect_triangle(s.w.data(), s.two_sided(), o, d, 0.0f);
        if (a > 1e-3 && b > 1e-3 && a + b < 1 - 1e-3) {
            REQUIRE(h.hit);
            Vec3d p = to_double(o) + to_double(d) * static_cast<double>(h.t);
            CHECK(std::abs(dot(p - v0, normalize(n))) < 1e-5);
            CHECK(std::abs(h.a - a) < 1e-4);
            CHECK(std::abs(h.b - b) < 1e-4);
        }
        // From behind: invisible to one-sided, visible to two-sided.
        Vec3f ob = to_float(target - normalize(n) * 2.0);
        Vec3f db = normalize(to_float(target) - ob);
        CHECK_FALSE(kernels::twins::intersect_triangle(s.w.data(), false, ob, db, 0.0f).hit);
        if (a > 1e-3 && b > 1e-3 && a + b < 1 - 1e-3)
            CHECK(kernels::twins::intersect_triangle(two_sided.shapes[0].w.data(), true, ob, db, 0.0f).hit);
    }
    // Outside the triangle: a miss.
    Vec3f o{3, 3, 3};
    CHECK_FALSE(kernels::twins::intersect_triangle(s.w.data(), true, o, normalize(Vec3f{2, 2, 0} - o), 0.0f).hit);
    // Parallel to the plane: a miss, no crash.
    CHECK_FALSE(kernels::twins::intersect_triangle(s.w.data(), true, Vec3f{0.5f, 0.1f, 0.5f}, Vec3f{1, 0, 0}, 0.0f).hit);
}

TEST_CASE("DDA twin: a connected walk through the voxels the ray crosses", "[twins][dda]") {
    kernels::twins::GridGeom g;
    g.lo = {-1, -2, 0};
    g.hi = {3, 2, 1};
    g.n[0] = 8;
    g.n[1] = 5;
    g.n[2] = 3;
    for (int k = 0; k < 3; ++k) {
        g.cell[k] = (g.hi[k] - g.lo[k]) / static_cast<float>(g.n[k]);
        g.inv_cell[k] = 1.0f / g.cell[k];
    }
    std::mt19937 rng(5);
    for (int trial = 0; trial < scaled(20000); ++trial) {
        Vec3f o = nesshi::rt::test::random_in(rng, Box{{-1, -2, 0}, {3, 2, 1}}, 0.5);
        Vec3f d = random_unit(rng);
        if (trial % 7 == 0) d[trial % 3] = 0.0f; // axis-parallel components
        if (trial % 11 == 0) d = Vec3f{0, 0, trial % 2 ? 1.0f : -1.0f};
        kernels::twins::DdaState s;
        if (!kernels::twins::dda_setup(g, o, d, 0.0f, std::numeric_limits<float>::infinity(), s)) continue;
        int steps = 0;
        int prev[3] = {s.i[0], s.i[1], s.i[2]};
        for (;;) {
            for (int k = 0; k < 3; ++k) REQUIRE((s.i[k] >= 0 && s.i[k] < g.n[k]));
            REQUIRE(s.addr == (s.i[2] * g.n[1] + s.i[1]) * g.n[0] + s.i[0]);
            // The midpoint of the voxel's t-span lies in (or on the border of) that voxel.
            float tout = s.voxel_exit();
            if (tout > s.t_in && std::isfinite(tout)) {
                float tm = 0.5f * (s.t_in + tout);
                for (int k = 0; k < 3; ++k) {
                    float c = (o[k] + tm * d[k] - g.lo[k]) * g.inv_cell[k];
                    CHECK(c >= static_cast<float>(s.i[k]) - 1e-3f);
                    CHECK(c <= static_cast<float>(s.i[k] + 1) + 1e-3f);
                }
            }
            if (!kernels::twins::dda_step(s)) break;
            int moved = 0;
            for (int k = 0; k < 3; ++k) moved += std::abs(s.i[k] - prev[k]);
            REQUIRE(moved == 1);
            for (int k = 0; k < 3; ++k) prev[k] = s.i[k];
            REQUIRE(++steps <= 8 + 5 + 3);
        }
    }
}
