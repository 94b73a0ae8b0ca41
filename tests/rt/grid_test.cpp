// Grid invariants: layout consistency, and every primitive listed in every voxel it touches.
#include "support.hpp"

#include "rt/grid.hpp"

#include <algorithm>
#include <cmath>
#include <random>

using namespace nesshi::rt;
using namespace nesshi::rt::test;

namespace {

std::size_t voxel_of(const Grid& g, Vec3d p) {
    int i[3];
    for (int k = 0; k < 3; ++k)
        i[k] = std::clamp(static_cast<int>(std::floor((p[k] - g.geom.lo[k]) / static_cast<double>(g.geom.cell[k]))), 0,
                          g.geom.n[k] - 1);
    return (static_cast<std::size_t>(i[2]) * static_cast<std::size_t>(g.geom.n[1]) + static_cast<std::size_t>(i[1])) *
               static_cast<std::size_t>(g.geom.n[0]) +
           static_cast<std::size_t>(i[0]);
}

bool listed(const Grid& g, std::size_t v, std::uint32_t si) {
    auto b = g.prims.begin() + g.offsets[v], e = g.prims.begin() + g.offsets[v + 1];
    return std::binary_search(b, e, si);
}

// A random point on the surface of shape si (double).
Vec3d surface_point(const Scene& sc, const ShapeSet& set, std::size_t si, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    const Shape& s = set.shapes[si];
    if (s.kind() == kShapeTriangle) {
        double a = u(rng), b = u(rng);
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        const auto& t = set.tri_verts[si];
        return t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b;
    }
    const Entity& e = sc.entities[static_cast<std::size_t>(s.entity)];
    Vec3d dir = to_double(random_unit(rng));
    if (e.kind == Entity::Kind::sphere) return e.base + dir * std::abs(e.base_r);
    Vec3d axis = normalize(e.apex - e.base);
    Vec3d radial = normalize(dir - axis * dot(dir, axis));
    double h = u(rng);
    double r = std::abs(e.base_r) + (std::abs(e.apex_r) - std::abs(e.base_r)) * h;
    return e.base + (e.apex - e.base) * h + radial * r;
}

void check_grid(const Scene& sc, int n) {
    ShapeSet set = build_shapes(sc);
    Grid g = build_grid(sc, set, n);
    const std::size_t nv = g.voxel_count();
    REQUIRE(nv == static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    REQUIRE(g.offsets.size() == nv + 1);
    REQUIRE(g.offsets.back() == g.prims.size());
    std::size_t empty = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        REQUIRE(g.offsets[v] <= g.offsets[v + 1]);
        const bool has = g.offsets[v] != g.offsets[v + 1];
        REQUIRE(g.occupancy[v] == (has ? 1 : 0));
        if (!has) ++empty;
        for (std::uint32_t k = g.offsets[v]; k + 1 < g.offsets[v + 1]; ++k) REQUIRE(g.prims[k] < g.prims[k + 1]);
    }
    CHECK(g.stats.empty_voxels == empty);
    CHECK(g.stats.references == g.prims.size());
    // Every listed primitive's bounds overlap the (padded) voxel: no stray references.
    for (int iz = 0; iz < n; ++iz)
        for (int iy = 0; iy < n; ++iy)
            for (int ix = 0; ix < n; ++ix) {
                std::size_t v = (static_cast<std::size_t>(iz) * static_cast<std::size_t>(n) + static_cast<std::size_t>(iy)) *
                                    static_cast<std::size_t>(n) + static_cast<std::size_t>(ix);
                Box vb = g.voxel_box(ix, iy, iz);
                vb.lo = vb.lo - Vec3d{g.pad, g.pad, g.pad};
                vb.hi = vb.hi + Vec3d{g.pad, g.pad, g.pad};
                for (std::uint32_t k = g.offsets[v]; k < g.offsets[v + 1]; ++k)
                    REQUIRE(box_box_overlap(set.bounds[g.prims[k]], vb));
            }
    // Brute force: sampled surface points of every primitive lie in voxels that list it.
    std::mt19937 rng(11);
    for (std::size_t si = 0; si < set.shapes.size(); ++si)
        for (int k = 0; k < scaled(200); ++k) {
            Vec3d p = surface_point(sc, set, si, rng);
            if (!listed(g, voxel_of(g, p), static_cast<std::uint32_t>(si))) {
                FAIL_CHECK("shape " << si << " (entity " << set.shapes[si].entity << ") not listed in voxel of point "
                                    << p.x << " " << p.y << " " << p.z);
                return;
            }
        }
    // Exact tests for spheres and triangles: listed exactly when the exact overlap test says so.
    for (std::size_t si = 0; si < set.shapes.size(); ++si) {
        const Shape& s = set.shapes[si];
        const Entity& e = sc.entities[static_cast<std::size_t>(s.entity)];
        if (e.kind == Entity::Kind::cylinder || e.kind == Entity::Kind::cone) continue;
        for (int iz = 0; iz < n; ++iz)
            for (int iy = 0; iy < n; ++iy)
                for (int ix = 0; ix < n; ++ix) {
                    Box vb = g.voxel_box(ix, iy, iz);
                    vb.lo = vb.lo - Vec3d{g.pad, g.pad, g.pad};
                    vb.hi = vb.hi + Vec3d{g.pad, g.pad, g.pad};
                    bool want = s.kind() == kShapeTriangle ? triangle_box_overlap(set.tri_verts[si], vb)
                                                           : sphere_box_overlap(e.base, std::abs(e.base_r), vb);
                    std::size_t v = (static_cast<std::size_t>(iz) * static_cast<std::size_t>(n) + static_cast<std::size_t>(iy)) *
                                        static_cast<std::size_t>(n) + static_cast<std::size_t>(ix);
                    if (listed(g, v, static_cast<std::uint32_t>(si)) != want) {
                        FAIL_CHECK("shape " << si << " voxel " << ix << " " << iy << " " << iz);
                        return;
                    }
                }
    }
}

} // namespace

TEST_CASE("Overlap tests", "[grid]") {
    Box b{{0, 0, 0}, {1, 1, 1}};
    CHECK(sphere_box_overlap({1.5, 0.5, 0.5}, 0.6, b));
    CHECK_FALSE(sphere_box_overlap({1.5, 1.5, 0.5}, 0.7, b)); // corner distance sqrt(0.5) = 0.707
    CHECK(sphere_box_overlap({1.5, 1.5, 0.5}, 0.71, b));
    CHECK(triangle_box_overlap({Vec3d{-1, -1, 0.5}, Vec3d{3, -1, 0.5}, Vec3d{-1, 3, 0.5}}, b)); // cuts through
    CHECK_FALSE(triangle_box_overlap({Vec3d{2, 0, 0}, Vec3d{0, 2, 0}, Vec3d{2, 2, 2}}, Box{{0, 0, 0}, {0.5, 0.5, 0.5}}));
    // Box corner region: the bounding boxes overlap but the triangle's plane misses the box.
    CHECK_FALSE(triangle_box_overlap({Vec3d{2.2, 0, 1}, Vec3d{0, 2.2, 1}, Vec3d{0, 0, 3.2}}, b));
    CHECK(auto_grid_resolution(8000) == 60);
    CHECK(auto_grid_resolution(1) == 4);
    CHECK(auto_grid_resolution(100000000) == 100);
}

TEST_CASE("Grid invariants on the small SPD scenes", "[grid]") {
    NESSHI_REQUIRE_SHARED();
    for (const std::string& f : small_scenes()) {
        Scene sc = load_nff_file(shared_spd(f));
        for (int n : {1, 7, scaled(10) == 10 ? 20 : 10}) {
            INFO(f << " grid " << n);
            check_grid(sc, n);
        }
    }
}

// `s 1e30 0 0 1` (or `s 1e8 0 0 1e-9`): the scene's extent on x vanishes next to its position,
// the cell size was 0, and the voxel range cast +-inf to int before the clamp (undefined; the
// release build printed a grid where the sphere was nowhere). The axis is widened instead.
TEST_CASE("a scene whose magnitude dwarfs its extent gets a usable grid", "[grid]") {
    for (const char* text : {"s 1e30 0 0 1\n", "s 1e8 0 0 1e-9\n", "s 0 -1e30 1e30 1e-3\n"}) {
        INFO(text);
        const Scene s = parse_nff(text, "far.nff");
        const ShapeSet set = build_shapes(s);
        const Grid g = build_grid(s, set, 10);
        for (int k = 0; k < 3; ++k) {
            CHECK(std::isfinite(g.geom.cell[k]));
            CHECK(g.geom.cell[k] > 0);
            CHECK(std::isfinite(g.geom.inv_cell[k]));
            CHECK(g.geom.lo[k] < g.geom.hi[k]);
        }
        CHECK(g.voxel_count() == 1000);
        CHECK(g.stats.references >= 1);
        CHECK(listed(g, voxel_of(g, s.entities[0].base), 0));
        // Rendering it is defined too (the sphere is far out of view; the image is background).
        PreparedScene p = prepare(s, 4);
        RenderOptions o;
        o.width = o.height = 4;
        o.threads = 1;
        CHECK(render_native(p, o).image.width == 4);
    }
    // An ordinary scene's grid is not touched by the widening: its box is the padded bounds.
    const Scene t = parse_nff("s 1 2 3 0.5\n", "near.nff");
    const Grid n = build_grid(t, build_shapes(t), 10);
    CHECK(n.box.lo.x == Approx(0.5 - 1e-4).epsilon(1e-9));
    CHECK(n.box.hi.z == Approx(3.5 + 1e-4).epsilon(1e-9));
}

TEST_CASE("grid resolutions above the limit are refused before any work", "[grid]") {
    const Scene s = parse_nff("s 0 0 0 1\n", "one.nff");
    CHECK_THROWS_WITH(build_grid(s, build_shapes(s), kMaxGridResolution + 1), "grid resolution is limited to 512");
    CHECK_NOTHROW(check_grid_resolution(kMaxGridResolution));
    CHECK_THROWS_AS(check_grid_resolution(2000), std::invalid_argument);
}
