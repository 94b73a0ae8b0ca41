// End to end on the SPD scenes: eye and shadow rays go through the OS kernel and the IC kernel
// (a minimal host moves VISIT, RETURN, HIT and MISS messages between them) and must give the
// native tracer's answer (rt::nearest_hit / rt::any_hit): same hit, shape, t, u, v, front bits.
#include "support.hpp"

#include "rt/camera.hpp"
#include "rt/grid.hpp"
#include "rt/scene.hpp"
#include "rt/shapes.hpp"
#include "rt/trace.hpp"

#include <cmath>
#include <optional>

using namespace nesshi;
using namespace nesshi::kernels;

namespace {

struct Pipeline {
    test::Rig os, ic;
    Pipeline(const std::string& os_file, const std::string& os_m, const std::string& ic_file, const std::string& ic_m,
             iss::Engine e)
        : os(os_file, os_m, e), ic(ic_file, ic_m, e) {}

    // Returns the HIT message, or nothing for a MISS.
    std::optional<abi::HitMsg> trace(std::uint32_t tag, const rt::Ray& r) {
        abi::NewRay nr{tag, {r.o.x, r.o.y, r.o.z}, {r.d.x, r.d.y, r.d.z}, r.tmin, r.tmax};
        os.feed(nr.words());
        for (int guard = 0; guard < 100000; ++guard) {
            os.run();
            const auto miss = os.out2.drain_all();
            if (!miss.empty()) {
                REQUIRE(miss.size() == 1);
                REQUIRE(os.out1.size() == 0);
                return std::nullopt;
            }
            const auto visit = os.out1.drain_all();
            REQUIRE(visit.size() == 12);
            ic.feed(visit);
            ic.run();
            const auto hit = ic.out2.drain_all();
            if (!hit.empty()) {
                REQUIRE(hit.size() == 6);
                return abi::HitMsg::from(hit.data());
            }
            const auto ret = ic.out1.drain_all();
            REQUIRE(ret.size() == 1);
            os.feed(ret);
        }
        FAIL("ray did not finish");
        return std::nullopt;
    }
};

void run_scene(const std::string& name, int grid_n, int pixels, bool seq) {
    const rt::Scene scene = rt::load_scene(name);
    const rt::ShapeSet set = rt::build_shapes(scene);
    const rt::Grid grid = rt::build_grid(scene, set, grid_n);
    Pipeline p(seq ? "seq/dda.s" : "os/dda.s", seq ? "seq" : "os", seq ? "seq/intersect.s" : "ic/intersect.s",
               seq ? "seq" : "ic", iss::Engine::Fast);
    p.os.load(os_image(grid.geom, grid.occupancy));
    p.os.run();
    const IcImage im = ic_image(grid.geom, grid.offsets, grid.prims, set.shapes);
    p.ic.load(im.resident);
    p.ic.load(im.global);
    p.ic.run();
    const rt::Camera cam(scene.view, pixels, pixels);
    long rays = 0, hits = 0, shadows = 0;
    for (int j = 0; j < pixels; ++j)
        for (int i = 0; i < pixels; ++i) {
            rt::Ray r = cam.eye_ray(i, j);
            r.d = abi::flush_direction(r.d);
            rt::TraceCounters c;
            const rt::Hit h = rt::nearest_hit(grid, set, r, c);
            const abi::Tag tag{static_cast<std::uint32_t>(rays % abi::kOsSlots), abi::Kind::eye, 1};
            INFO(name << " pixel " << i << "," << j);
            const auto got = p.trace(tag.word(), r);
            ++rays;
            REQUIRE(got.has_value() == h.hit);
            if (!h.hit) continue;
            ++hits;
            CHECK(got->shape == static_cast<std::uint32_t>(h.shape));
            CHECK(test::fbits(got->t) == test::fbits(h.t));
            if (set.shapes[static_cast<std::size_t>(h.shape)].kind() == kernels::kShapeTriangle) {
                CHECK(test::fbits(got->u) == test::fbits(h.a));
                CHECK(test::fbits(got->v) == test::fbits(h.b));
            }
            CHECK(got->front == (h.front ? 1u : 0u));
            // a shadow ray from the hit point to each light
            const base::Vec3f hp = r.o + r.d * h.t;
            for (const rt::Light& l : scene.lights) {
                const base::Vec3f lp = base::to_float(l.pos);
                const base::Vec3f to = lp - hp;
                const float dist = std::sqrt(base::dot(to, to));
                if (!(dist > 0)) continue;
                rt::Ray s;
                s.o = hp;
                s.d = abi::flush_direction(to * (1.0f / dist));
                s.tmin = 1e-3f;
                s.tmax = dist;
                s.kind = rt::RayKind::shadow;
                const bool blocked = rt::any_hit(grid, set, s, c);
                const abi::Tag st{static_cast<std::uint32_t>((rays + 7) % abi::kOsSlots), abi::Kind::shadow, 2};
                const auto sg = p.trace(st.word(), s);
                CHECK(sg.has_value() == blocked);
                ++shadows;
            }
        }
    WARN(name << " on " << (seq ? "seq" : "os+ic") << ": " << rays << " eye rays (" << hits << " hits), " << shadows
              << " shadow rays");
}

} // namespace

TEST_CASE("os + ic kernels trace the SPD scenes like the native tracer", "[unit][kernels][scene]") {
    for (const char* s : {"balls:1", "mount:1", "rings:1", "tetra:1", "tree:1"}) run_scene(s, 8, 24, false);
}

TEST_CASE("seq kernels trace the SPD scenes like the native tracer", "[unit][kernels][scene]") {
    for (const char* s : {"tetra:1", "tree:1"}) run_scene(s, 6, 16, true);
}
