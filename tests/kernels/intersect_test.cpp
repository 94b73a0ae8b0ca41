// Differential test of the IC intersection kernel (kernels/ic/intersect.s) against the native
// twins (kernels/twins/triangle.hpp, quadric.hpp) and the closest-hit / any-hit rules of rt/trace.cpp:
// same HIT or RETURN, same shape, bit-identical t, u, v and front, on random primitives and rays.
#include "support.hpp"

#include "kernels/twins/quadric.hpp"
#include "kernels/twins/triangle.hpp"
#include "rt/shapes.hpp"

#include <algorithm>
#include <limits>

using namespace nesshi;
using namespace nesshi::kernels;
using nesshi::base::Vec3d;
using nesshi::base::Vec3f;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

kernels::Shape quadric(std::mt19937& rng, bool two_sided) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), pos(-4.0, 4.0), rad(0.2, 1.5);
    kernels::Shape s;
    s.kind_flags = kernels::kShapeQuadric | (two_sided ? kernels::kShapeTwoSided : 0u);
    const int kind = static_cast<int>(rng() % 4);
    const Vec3d c{pos(rng), pos(rng), pos(rng)};
    const double r = rad(rng);
    double m[10] = {1, 1, 1, 0, 0, 0, 0, 0, 0, -r * r};
    Vec3d a{0, 0, 0};
    double len = 0;
    if (kind == 1 || kind == 2) { // cylinder / cone along a random axis
        a = base::normalize(Vec3d{u(rng), u(rng), u(rng)});
        len = rad(rng) * 3.0;
        if (kind == 1) {
            m[0] = 1 - a.x * a.x, m[1] = 1 - a.y * a.y, m[2] = 1 - a.z * a.z;
            m[3] = -a.x * a.y, m[4] = -a.y * a.z, m[5] = -a.z * a.x;
        } else { // cone with apex at c, opening k: |p|^2 - (1 + k^2)(a.p)^2 = 0 (shifted radius)
            const double k2 = 1.0 + 0.25;
            m[0] = 1 - k2 * a.x * a.x, m[1] = 1 - k2 * a.y * a.y, m[2] = 1 - k2 * a.z * a.z;
            m[3] = -k2 * a.x * a.y, m[4] = -k2 * a.y * a.z, m[5] = -k2 * a.z * a.x;
            m[9] = -0.01;
        }
    } else if (kind == 3) { // arbitrary coefficients
        for (double& x : m) x = u(rng);
    }
    if (rng() % 5 == 0)
        for (double& x : m) x = -x; // inside-visible: Q negated
    s.w[0] = static_cast<float>(c.x), s.w[1] = static_cast<float>(c.y), s.w[2] = static_cast<float>(c.z);
    for (int i = 0; i < 10; ++i) s.w[static_cast<std::size_t>(3 + i)] = static_cast<float>(m[i]);
    s.w[13] = static_cast<float>(a.x), s.w[14] = static_cast<float>(a.y), s.w[15] = static_cast<float>(a.z);
    s.w[16] = static_cast<float>(len);
    return s;
}

struct Expect {
    bool hit = false;
    std::uint32_t shape = 0;
    float t = 0, u = 0, v = 0;
    std::uint32_t front = 0;
};

struct Ray {
    Vec3f o, d;
    float tmin, tmax, t_out;
    bool shadow;
};

// The native rules: rt/trace.cpp's nearest_hit inner loop (eye and secondary rays) and any_hit.
Expect reference(const std::vector<kernels::Shape>& shapes, const std::vector<std::uint32_t>& list, const Ray& r) {
    Expect best;
    float best_t = kInf;
    for (std::uint32_t si : list) {
        const kernels::Shape& s = shapes[si];
        bool hit;
        float t, u = 0, v = 0;
        bool front = true;
        if (s.kind() == kernels::kShapeTriangle) {
            const auto h = kernels::twins::intersect_triangle(s.w.data(), s.two_sided(), r.o, r.d, r.tmin);
            hit = h.hit, t = h.t, u = h.a, v = h.b;
        } else {
            const auto h = kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), r.o, r.d, r.tmin);
            hit = h.hit, t = h.t, front = h.front;
        }
        // shadow rays: any hit before tmax kills the ray (rt::any_hit, no voxel bound); the
        // kernel reports the nearest such hit of the voxel
        if (!hit || !(r.shadow || t <= r.t_out) || !(t < r.tmax)) continue;
        if (t < best_t) {
            best_t = t;
            best = {true, si, t, u, v, front ? 1u : 0u};
        }
    }
    return best;
}

// `prog` on random lists of `nshapes` shapes: each list holds about a third of them (one holds
// one, one none), or with `any_length` from 0 to `nshapes` shapes.
void run_ic(const std::shared_ptr<const iss::Program>& prog, iss::Engine engine, int scenes, int rays, std::uint32_t seed,
            int nshapes = 30, bool any_length = false) {
    const std::string machine = prog->machine().name;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-4.0, 4.0), u01(0.0, 1.0);
    std::uniform_real_distribution<float> uf(0.0f, 1.0f);
    long tests = 0, hits = 0, tri_tests = 0, quad_tests = 0;
    for (int sc = 0; sc < scenes; ++sc) {
        std::vector<kernels::Shape> shapes;
        std::vector<std::array<Vec3d, 3>> verts;
        const double quad_share = sc % 3 == 0 ? 0.0 : (sc % 3 == 1 ? 1.0 : 0.4);
        for (int i = 0; i < nshapes; ++i) {
            const std::uint32_t dup = i > 0 ? static_cast<std::uint32_t>(rng() % 12) : 12;
            if (dup == 0) { // an exact duplicate: a t tie, the lower index must win
                shapes.push_back(shapes.back());
                verts.push_back(verts.back());
                continue;
            }
            if (dup == 1 && shapes.back().kind() == kernels::kShapeTriangle) { // the same triangle with the other sidedness: a tie
                shapes.push_back(shapes.back());     // across kinds (a kernel of per-kind runs meets
                shapes.back().kind_flags ^= kernels::kShapeTwoSided; // them in other runs)
                verts.push_back(verts.back());
                continue;
            }
            if (u01(rng) < quad_share) {
                shapes.push_back(quadric(rng, rng() % 2 == 0));
                verts.push_back({});
            } else {
                std::array<Vec3d, 3> v{Vec3d{pos(rng), pos(rng), pos(rng)}, Vec3d{pos(rng), pos(rng), pos(rng)},
                                       Vec3d{pos(rng), pos(rng), pos(rng)}};
                shapes.push_back(rt::triangle_record(v[0], v[1], v[2], rng() % 3 == 0));
                verts.push_back(v);
            }
            shapes.back().entity = i;
        }
        std::vector<std::vector<std::uint32_t>> lists(any_length ? 12 : 6);
        for (std::size_t v = 0; v < lists.size(); ++v) {
            const double share = any_length ? u01(rng) : v == 0 ? 0.0 : 0.35;
            for (std::uint32_t i = 0; i < shapes.size(); ++i)
                if (u01(rng) < share) lists[v].push_back(i);
        }
        if (!any_length) lists[5].resize(std::min<std::size_t>(lists[5].size(), 1));
        test::Rig rig(prog, engine);
        const IcImage im = ic_image_lists(lists, shapes, true, kbuild::list_layout(*rig.prog));
        rig.load(im.resident);
        rig.load(im.global);
        rig.run();
        for (int ri = 0; ri < rays; ++ri) {
            Ray r;
            r.o = base::to_float(Vec3d{pos(rng) * 2, pos(rng) * 2, pos(rng) * 2});
            const std::uint32_t target_shape = static_cast<std::uint32_t>(rng() % shapes.size());
            Vec3d target{pos(rng), pos(rng), pos(rng)};
            if (shapes[target_shape].kind() == kernels::kShapeTriangle) { // aim at the triangle, its edges, its vertices
                const auto& v = verts[target_shape];
                double a = u01(rng), b = u01(rng) * (1 - a);
                if (ri % 5 == 0) b = 1 - a;     // on an edge: grazing
                if (ri % 7 == 0) a = 0, b = 0;  // at a vertex
                target = v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b;
            } else {
                const kernels::Shape& q = shapes[target_shape];
                target = Vec3d{q.w[0] + pos(rng) * 0.3, q.w[1] + pos(rng) * 0.3, q.w[2] + pos(rng) * 0.3};
            }
            Vec3d d = target - base::to_double(r.o);
            if (ri % 11 == 0) d = Vec3d{0, 0, d.z}; // axis-parallel
            if (!(base::dot(d, d) > 0)) d = {0, 0, 1};
            r.d = abi::flush_direction(base::to_float(base::normalize(d)));
            r.tmin = ri % 2 ? 0.0f : uf(rng) * 0.01f;
            r.tmax = ri % 3 == 0 ? kInf : uf(rng) * 30.0f;
            r.t_out = ri % 4 == 0 ? r.tmax : uf(rng) * 30.0f;
            if (!(r.t_out < kInf)) r.t_out = 1e30f;
            r.shadow = ri % 5 == 3;
            const std::uint32_t voxel = static_cast<std::uint32_t>(ri % static_cast<int>(lists.size()));
            const Expect e = reference(shapes, lists[voxel], r);
            for (std::uint32_t si : lists[voxel]) (shapes[si].kind() == kernels::kShapeTriangle ? tri_tests : quad_tests)++;
            abi::Tag tag{static_cast<std::uint32_t>(ri), r.shadow ? abi::Kind::shadow : abi::Kind::eye, 1};
            abi::Visit vis;
            vis.tag = tag.word() | abi::kTagReturn;
            vis.voxel = voxel;
            vis.t_in = r.tmin;
            vis.t_out = r.t_out;
            for (int k = 0; k < 3; ++k) vis.o[k] = r.o[k], vis.d[k] = r.d[k];
            vis.tmin = r.tmin;
            vis.tmax = r.tmax;
            rig.feed(vis.words());
            rig.run();
            INFO("scene " << sc << " ray " << ri << " voxel " << voxel << " shadow " << r.shadow << " expect hit "
                          << e.hit << " shape " << e.shape << " t " << e.t);
            if (!e.hit) {
                REQUIRE(rig.out2.size() == 0);
                const auto w = rig.out1.drain_all();
                REQUIRE(w.size() == 1);
                CHECK(w[0] == vis.tag);
            } else {
                ++hits;
                REQUIRE(rig.out1.size() == 0);
                const auto w = rig.out2.drain_all();
                REQUIRE(w.size() == 6);
                const abi::HitMsg h = abi::HitMsg::from(w.data());
                CHECK(h.tag == tag.word());
                CHECK(h.shape == e.shape);
                CHECK(test::fbits(h.t) == test::fbits(e.t));
                CHECK(test::fbits(h.u) == test::fbits(e.u));
                CHECK(test::fbits(h.v) == test::fbits(e.v));
                CHECK(h.front == e.front);
            }
            ++tests;
        }
    }
    WARN(machine << ": " << tests << " rays, " << hits << " hits, " << tri_tests << " triangle and " << quad_tests
                 << " quadric tests compared");
}

} // namespace

TEST_CASE("ic intersection kernel matches the twins (fast engine)", "[unit][kernels][intersect]") {
    run_ic(test::kernel_program("ic/intersect.s", "ic"), iss::Engine::Fast, 60, 400, 11);
}

TEST_CASE("ic intersection kernel matches the twins (checked engine)", "[unit][kernels][intersect]") {
    run_ic(test::kernel_program("ic/intersect.s", "ic"), iss::Engine::Checked, 12, 200, 12);
}

// ic-real: the kernel chosen for it on the kernel workloads (the hybrid of intersect.pk and
// intersect.loops.pk; only its lists of 8 or more shapes take the loops: see the hybrid test below).
TEST_CASE("ic intersection kernel scheduled for ic-real matches the twins", "[unit][kernels][intersect]") {
    run_ic(test::kernel_program("ic/intersect.s", "ic-real"), iss::Engine::Fast, 30, 300, 15);
}

// A machine whose long lists run fastest through the hybrid kernel (the dispatch bodies for short
// lists, the per-kind loops after a LOOPS record for long ones): lists of 0 to 40 shapes of mixed
// kinds, with ties, take either path, on both sides of its threshold.
TEST_CASE("the hybrid ic kernel matches the twins on both paths", "[unit][kernels][intersect]") {
    const isa::Machine m = isa::parse_machine("inherits = \"ic\"\nname = \"ic-long-alu\"\nbranch_penalty = 1\n"
                                              "[latency]\nalu = 12\nmul = 2\nfadd = 2\nfmul = 2\nfdiv = 2\nload = 10\n"
                                              "store = 8\nbranch = 11\nfifo = 6\nmisc = 2\n",
                                              "ic-long-alu.toml");
    kbuild::KernelBuild build;
    const auto prog = kbuild::assemble_kernel(embedded(), "ic/intersect.s", m, &build);
    INFO(build.choice);
    REQUIRE(build.choice.find("for lists of") != std::string::npos);
    REQUIRE(kbuild::list_layout(*prog).long_from > 0);
    const std::uint32_t from = kbuild::list_layout(*prog).long_from;
    INFO("lists of " << from << " or more take the loops");
    run_ic(prog, iss::Engine::Fast, 16, 300, 16, 40, true);
    run_ic(prog, iss::Engine::Checked, 4, 100, 17, 40, true);
}

TEST_CASE("seq intersection kernel matches the twins (fast engine)", "[unit][kernels][intersect]") {
    run_ic(test::kernel_program("seq/intersect.s", "seq"), iss::Engine::Fast, 30, 400, 13);
}

TEST_CASE("seq intersection kernel matches the twins (checked engine)", "[unit][kernels][intersect]") {
    run_ic(test::kernel_program("seq/intersect.s", "seq"), iss::Engine::Checked, 8, 200, 14);
}
