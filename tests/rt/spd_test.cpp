// SPD generators against the reference NFF files: same entities in order, numbers within 1e-5 relative.
#include "support.hpp"

#include "rt/spd.hpp"

#include <cmath>

using namespace nesshi::rt;
using namespace nesshi::rt::test;

namespace {

// Relative 1e-5, with an absolute floor of 1e-9 for values that are zero up to rounding (-2.5e-17).
bool close(double a, double b) { return std::abs(a - b) <= 1e-5 * std::max(std::abs(a), std::abs(b)) + 1e-9; }
bool close(Vec3d a, Vec3d b) { return close(a.x, b.x) && close(a.y, b.y) && close(a.z, b.z); }

void compare(const Scene& g, const Scene& r) {
    REQUIRE(g.entities.size() == r.entities.size());
    REQUIRE(g.lights.size() == r.lights.size());
    REQUIRE(g.materials.size() == r.materials.size());
    CHECK(close(g.view.from, r.view.from));
    CHECK(close(g.view.at, r.view.at));
    CHECK(close(g.view.up, r.view.up));
    CHECK(g.view.angle == r.view.angle);
    for (std::size_t i = 0; i < g.lights.size(); ++i) CHECK(close(g.lights[i].pos, r.lights[i].pos));
    for (std::size_t i = 0; i < g.materials.size(); ++i) {
        const Material &a = g.materials[i], &b = r.materials[i];
        CHECK((close(a.color.r, b.color.r) && close(a.color.g, b.color.g) && close(a.color.b, b.color.b)));
        CHECK((close(a.kd, b.kd) && close(a.ks, b.ks) && close(a.shine, b.shine) && close(a.t, b.t) && close(a.ior, b.ior)));
    }
    int bad = 0;
    for (std::size_t i = 0; i < g.entities.size(); ++i) {
        const Entity &a = g.entities[i], &b = r.entities[i];
        bool ok = a.kind == b.kind && a.material == b.material && close(a.base, b.base) && close(a.apex, b.apex) &&
                  close(a.base_r, b.base_r) && close(a.apex_r, b.apex_r) && a.verts.size() == b.verts.size() &&
                  a.normals.size() == b.normals.size();
        for (std::size_t v = 0; ok && v < a.verts.size(); ++v) ok = close(a.verts[v], b.verts[v]);
        if (!ok && ++bad <= 3) FAIL_CHECK("entity " << i << " differs (" << b.loc.str() << ")");
    }
    CHECK(bad == 0);
}

} // namespace

TEST_CASE("SPD names", "[spd]") {
    CHECK(parse_spd_name("balls")->size == 0);
    CHECK(parse_spd_name("tree:3")->size == 3);
    CHECK_FALSE(parse_spd_name("foo.nff"));
    CHECK_THROWS(parse_spd_name("balls:zero"));
    CHECK_THROWS(generate_spd("nope", 1));
    CHECK_THROWS(generate_spd("mount", 8));
    CHECK(spd_names().size() == 5);
}

TEST_CASE("SPD generators equal the reference files", "[spd]") {
    NESSHI_REQUIRE_SHARED();
    struct Case {
        const char* name;
        int size;
        const char* file;
    };
    const Case cases[] = {{"balls", 1, "balls-s1.nff"}, {"balls", 2, "balls-s2.nff"}, {"balls", 3, "balls-s3.nff"},
                          {"balls", 0, "balls.nff"},    {"mount", 2, "mount-s2.nff"}, {"mount", 3, "mount-s3.nff"},
                          {"mount", 0, "mount.nff"},    {"rings", 1, "rings-s1.nff"}, {"rings", 2, "rings-s2.nff"},
                          {"rings", 0, "rings.nff"},    {"tetra", 2, "tetra-s2.nff"}, {"tetra", 3, "tetra-s3.nff"},
                          {"tetra", 0, "tetra.nff"},    {"tree", 3, "tree-s3.nff"},   {"tree", 5, "tree-s5.nff"},
                          {"tree", 0, "tree.nff"},      {"gears", 1, "gears-s1.nff"}, {"gears", 0, "gears.nff"}};
    for (const Case& c : cases) {
        INFO(c.file);
        std::string text = generate_spd(c.name, c.size);
        Scene gen = parse_nff(text, c.name);
        Scene ref = load_nff_file(shared_spd(c.file));
        compare(gen, ref);
    }
}

TEST_CASE("Built-in names load like files", "[spd]") {
    Scene s = load_scene("tetra:2");
    CHECK(s.name == "tetra:2");
    CHECK(s.entities.size() == 16);
    CHECK(count(load_scene("rings:1")).cylinders == 30);
    CHECK(count(load_scene("tree:3")).cones == 15);
}
