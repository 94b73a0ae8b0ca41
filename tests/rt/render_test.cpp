// Renderer: ray counts equal a brute-force tracer's; the same image and stats for any thread count.
#include "support.hpp"

#include "rt/camera.hpp"
#include "rt/render.hpp"

#include <algorithm>
#include <cmath>

using namespace nesshi::rt;
using namespace nesshi::rt::test;

namespace {
bool same_traversal(const RenderStats& a, const RenderStats& b) {
    for (std::size_t k = 0; k < kRayKinds; ++k) {
        const TraceCounters &x = a.traversal[k], &y = b.traversal[k];
        if (x.rays != y.rays || x.voxel_steps != y.voxel_steps || x.nonempty_voxels != y.nonempty_voxels ||
            x.triangle_tests != y.triangle_tests || x.quadric_tests != y.quadric_tests ||
            x.quadric_two_roots != y.quadric_two_roots)
            return false;
    }
    return true;
}
} // namespace

TEST_CASE("Camera: corner rays follow the SPD conventions", "[render]") {
    View v;
    v.from = {0, -5, 0};
    v.at = {0, 0, 0};
    v.up = {0, 0, 1};
    v.angle = 90;
    Camera cam(v, 4, 2);
    Ray c = cam.eye_ray(2, 1); // image centre
    CHECK(c.d.x == Approx(0).margin(1e-7));
    CHECK(c.d.y == Approx(1));
    CHECK(c.d.z == Approx(0).margin(1e-7));
    Ray tl = cam.eye_ray(0, 0); // top-left corner: left (-x) and up (+z)
    CHECK(tl.d.x < 0);
    CHECK(tl.d.z > 0);
    // s = tan(45 deg) * W/(W-1) = 4/3; corner u = -s, v = s*H/W
    CHECK(tl.d.x / tl.d.y == Approx(-4.0 / 3.0));
    CHECK(tl.d.z / tl.d.y == Approx(4.0 / 3.0 * 2.0 / 4.0));
    CHECK(std::sqrt(dot(tl.d, tl.d)) == Approx(1).epsilon(1e-6));
}

TEST_CASE("Ray counts on the small scenes equal the brute-force tracer", "[render]") {
    NESSHI_REQUIRE_SHARED();
    const int size = scaled(100) < 20 ? 24 : 64;
    for (const char* f : {"balls-s1.nff", "balls-s2.nff", "mount-s2.nff", "rings-s1.nff", "tetra-s2.nff",
                                 "tree-s3.nff", "teapot-s2.nff", "gears-s1.nff"}) {
        INFO(f);
        PreparedScene p = prepare(load_nff_file(shared_spd(f)), 20);
        RenderOptions o;
        o.width = o.height = size;
        o.threads = 2;
        o.id_buffer = o.t_buffer = true;
        RenderResult g = render_native(p, o);
        o.brute_force = true;
        RenderResult b = render_native(p, o);
        CHECK(g.stats.rays == b.stats.rays);
        CHECK(g.image.rgb == b.image.rgb);
        CHECK(g.id_buffer == b.id_buffer);
        CHECK(g.t_buffer == b.t_buffer);
        CHECK(g.stats.rays.eye_rays == static_cast<std::uint64_t>((size + 1) * (size + 1)));
        CHECK(g.stats.rays.eye_rays_hit > 0);
        CHECK(g.stats.rays.shadow_rays > 0);
        CHECK(g.stats.traversal[0].rays == g.stats.rays.eye_rays);
        CHECK(g.stats.traversal[1].rays == g.stats.rays.shadow_rays);
        CHECK(g.stats.traversal[2].rays == g.stats.rays.reflection_rays);
        CHECK(g.stats.traversal[3].rays == g.stats.rays.refraction_rays);
    }
}

TEST_CASE("The same image and stats for any thread count", "[render]") {
    NESSHI_REQUIRE_SHARED();
    PreparedScene p = prepare(load_nff_file(shared_spd("mount-s3.nff")), 0);
    RenderOptions o;
    o.width = 48;
    o.height = 40;
    o.id_buffer = o.t_buffer = true;
    o.threads = 1;
    RenderResult one = render_native(p, o);
    CHECK(one.stats.rays.refraction_rays > 0); // mount has glass spheres
    for (int t : {2, 3, 7}) {
        o.threads = t;
        RenderResult r = render_native(p, o);
        CHECK(r.image.rgb == one.image.rgb);
        CHECK(r.stats.rays == one.stats.rays);
        CHECK(same_traversal(r.stats, one.stats));
        CHECK(r.id_buffer == one.id_buffer);
        CHECK(r.t_buffer == one.t_buffer);
    }
}

TEST_CASE("Stats JSON carries the required keys", "[render]") {
    PreparedScene p = prepare(parse_nff("v from 0 -5 0 at 0 0 0 up 0 0 1 angle 40 resolution 8 8\nl 0 -5 5\n"
                                        "f 1 1 1 0.5 0.5 10 0 1\ns 0 0 0 1\n",
                                        "mini.nff"),
                              4);
    RenderOptions o;
    o.width = o.height = 8;
    RenderResult r = render_native(p, o);
    std::string j = stats_text(stats_json(p, o, r, "native"));
    for (const char* key : {"\"scene\"", "\"size\"", "\"grid\"", "\"model\"", "\"rays\"", "\"eye_rays\"",
                            "\"eye_rays_hit\"", "\"shadow_rays\"", "\"shadow_rays_blocked\"", "\"reflection_rays\"",
                            "\"refraction_rays\"", "\"secondary_rays_hit\"", "\"total_internal_reflections\"",
                            "\"traversal\"", "\"voxel_steps\"", "\"host\"", "\"setup_seconds\"", "\"trace_seconds\"",
                            "\"epsilon\"", "\"schema\""})
        CHECK(j.find(key) != std::string::npos);
    CHECK(r.stats.rays.eye_rays == 81);
    CHECK(r.stats.rays.eye_rays_hit > 0);
}

TEST_CASE("Automatic grid resolution by pre-pass", "[render]") {
    NESSHI_REQUIRE_SHARED();
    Scene sc = load_nff_file(shared_spd("mount-s2.nff"));
    ShapeSet set = build_shapes(sc);
    GridChoice a = choose_grid_resolution(sc, set), b = choose_grid_resolution(sc, set);
    REQUIRE(a.costs.size() == 5);
    CHECK(a.n == b.n);
    CHECK(a.costs == b.costs);
    for (auto [n, cost] : a.costs) {
        CHECK(cost > 0);
        if (n != a.n) CHECK(cost >= std::find_if(a.costs.begin(), a.costs.end(), [&](auto& c) { return c.first == a.n; })->second);
    }
    CHECK(prepare(sc, 0).grid.stats.n[0] == a.n);
}
