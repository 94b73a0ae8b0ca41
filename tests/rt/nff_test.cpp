// NFF reader: the accepted syntax, and bad input giving file:line:col errors without crashing.
#include "support.hpp"

#include "rt/scene.hpp"

#include <algorithm>
#include <random>

using namespace nesshi::rt;

namespace {
std::string error_of(const std::string& text) {
    try {
        parse_nff(text, "t.nff");
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST_CASE("NFF: all entities, comments and free white space", "[nff]") {
    const char* text = "# a comment\n"
                       "v from 0 -5 0  at 0 0 0\nup 0 0 1 angle 40 hither 0.5 resolution 64 32\n"
                       "b 0.1 0.2 0.3\n"
                       "l 1 2 3\n l 4 5 6 0.5 0.5 0.5 # coloured\n"
                       "f 1 0 0 0.7 0.3 10 0 1\n"
                       "s 0 0 0 1\n"
                       "c 0 0 0 1 0 0 2 1   c 0 0 0 1 0 0 2 0.5\n"
                       "p 3\n0 0 0\n1 0 0\n0 1 0\n"
                       "f 1 1 1 0 0 0 0.9 1.5\n"
                       "pp 3 0 0 0 0 0 1  1 0 0 0 0 1  0 1 0 0 0 1\n"
                       "s 5 5 5 -2\n";
    Scene s = parse_nff(text, "ok.nff");
    REQUIRE(s.entities.size() == 6);
    CHECK(s.view.width == 64);
    CHECK(s.view.height == 32);
    CHECK(s.view.angle == 40);
    CHECK(s.lights.size() == 2);
    CHECK_FALSE(s.lights[0].has_color);
    CHECK(s.lights[1].has_color);
    CHECK(s.materials.size() == 2);
    CHECK(s.entities[0].kind == Entity::Kind::sphere);
    CHECK(s.entities[1].kind == Entity::Kind::cylinder);
    CHECK(s.entities[2].kind == Entity::Kind::cone);
    CHECK(s.entities[3].kind == Entity::Kind::polygon);
    CHECK(s.entities[4].kind == Entity::Kind::patch);
    CHECK(s.entities[4].material == 1);
    CHECK(s.entities[5].base_r == -2);
    CHECK(s.entities[3].loc.line == 10);
    CHECK(s.entities[3].loc.col == 1);
    CHECK(s.entities[1].loc.str() == "ok.nff:9:1");
    CHECK(s.entities[2].loc.col == 21);
    SceneCounts c = count(s);
    CHECK(c.spheres == 2);
    CHECK(c.cylinders == 1);
    CHECK(c.cones == 1);
    CHECK(c.polygons == 1);
    CHECK(c.patches == 1);
    CHECK(c.transmitting == 2);
    CHECK(c.reflective == 4);
}

TEST_CASE("NFF: malformed input gives file:line:col errors", "[nff][bad-input]") {
    CHECK(error_of("s 0 0 zero 1\n") == "t.nff:1:7: error: expected a sphere centre coordinate (a number), got 'zero'");
    CHECK(error_of("s 0 0 0\n") == "t.nff:2:1: error: expected the sphere radius but the file ended");
    CHECK(error_of("\n  q 1 2\n") == "t.nff:2:3: error: unknown entity 'q' (expected v, b, l, f, c, s, p or pp)");
    CHECK(error_of("s 0 0 nan 1") == "t.nff:1:7: error: a sphere centre coordinate must be finite, got 'nan'");
    CHECK(error_of("s 0 0 inf 1").find("must be finite") != std::string::npos);
    CHECK(error_of("s 0 0 1e999 1").find("t.nff:1:7: error:") == 0);
    CHECK(error_of("s 0 0 0 0").find("t.nff:1:9: error: sphere radius is zero") == 0);
    CHECK(error_of("p 4\n0 0 0\n1 0 0\n0 1 0\ns 0 0 0 1\n") ==
          "t.nff:5:1: error: polygon declares 4 vertices but vertex 4 is missing (found 's')");
    CHECK(error_of("p 3\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n") ==
          "t.nff:5:1: error: polygon declares 3 vertices but more numbers follow");
    CHECK(error_of("p 2\n0 0 0\n1 0 0\n").find("t.nff:1:3: error: the vertex count must be an integer in [3,") == 0);
    CHECK(error_of("p 3.5\n").find("t.nff:1:3: error: the vertex count must be an integer") == 0);
    CHECK(error_of("p 3\n0 0 0\n1 1 1\n2 2 2\n") ==
          "t.nff:1:1: error: degenerate polygon: its first three vertices are collinear or repeated");
    CHECK(error_of("p 3\n0 0 0\n0 0 0\n1 0 0\n").find("degenerate polygon") != std::string::npos);
    CHECK(error_of("c 0 0 0 1 0 0 0 1") == "t.nff:1:1: error: cone base and apex are the same point");
    CHECK(error_of("c 0 0 0 0 0 0 1 0").find("both cone radii are zero") != std::string::npos);
    CHECK(error_of("f 1 1 1 1 0 0 2 1").find("t.nff:1:15: error: T (transmittance) must be in [0, 1]") == 0);
    CHECK(error_of("f 1 1 1 1 0 0 1").find("expected the index of refraction but the file ended") != std::string::npos);
    CHECK(error_of("v from 0 0 0 at 0 0 0 up 0 0 1") == "t.nff:1:1: error: view 'from' and 'at' are the same point");
    CHECK(error_of("v from 0 0 0 at 0 0 1 up 0 0 1").find("parallel") != std::string::npos);
    CHECK(error_of("v from 0 0 0 up 0 0 1") == "t.nff:1:1: error: view has no 'at' line");
    CHECK(error_of("v from 0 0 0 at 1 0 0 up 0 0 1 angle 0").find("t.nff:1:38: error: the view angle") == 0);
    CHECK(error_of("v from 0 0 0 at 1 0 0 up 0 0 1 resolution 0 5").find("resolution width") != std::string::npos);
    CHECK(error_of("v from 0 0 0 from 1 1 1").find("'from' given twice") != std::string::npos);
    CHECK(error_of("pp 3 0 0 0 0 0 0  1 0 0 0 0 1  0 1 0 0 0 1").find("t.nff:1:12: error: patch vertex normal is zero") == 0);
    CHECK(error_of("l 1 2").find("expected a light coordinate but the file ended") != std::string::npos);
    CHECK(error_of("b 1 2 x").find("t.nff:1:7:") == 0);
}

TEST_CASE("NFF: missing file and built-in name errors", "[nff][bad-input]") {
    CHECK_THROWS_WITH(load_nff_file("/nonexistent/x.nff"), "/nonexistent/x.nff: error: cannot open: No such file or directory");
    CHECK_THROWS_AS(load_scene("balls:0"), SceneError);
    CHECK_THROWS_AS(load_scene("balls:x"), SceneError);
}

// Scenes are read through base::read_file: a directory or a device is a SceneError naming it,
// never an empty scene or a read that runs until memory is exhausted.
TEST_CASE("NFF: directories and devices are refused", "[nff][bad-input]") {
    CHECK_THROWS_WITH(load_scene("/"), "/: error: is a directory");
    CHECK_THROWS_WITH(load_scene("/dev/zero"), "/dev/zero: error: not a regular file");
    CHECK_THROWS_AS(load_nff_file("/dev/zero"), SceneError);
}

TEST_CASE("NFF: random corruption of a valid file never crashes", "[nff][bad-input]") {
    const std::string good = "v from 0 -5 0 at 0 0 0 up 0 0 1 angle 40 hither 0.5 resolution 8 8\n"
                             "l 1 2 3\nf 1 0 0 0.7 0.3 10 0 1\ns 0 0 0 1\nc 0 0 0 1 0 0 2 0.5\n"
                             "p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    std::mt19937 rng(7);
    const std::string junk = " \n#-+.e0123456789xnaNpcsflvb";
    int errors = 0;
    for (int trial = 0; trial < nesshi::rt::test::scaled(3000); ++trial) {
        std::string s = good;
        int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            std::size_t at = rng() % s.size();
            switch (rng() % 3) {
            case 0: s[at] = junk[rng() % junk.size()]; break;
            case 1: s = s.substr(0, at) + s.substr(std::min(s.size(), at + 1 + rng() % 6)); break;
            default: s = s.substr(0, at) + junk[rng() % junk.size()] + s.substr(at); break;
            }
            if (s.empty()) s = "x";
        }
        try {
            Scene sc = parse_nff(s, "fuzz.nff");
            ShapeSet set = build_shapes(sc); // every accepted scene must also build
            (void)set;
        } catch (const SceneError& ex) {
            ++errors;
            CHECK(std::string(ex.what()).rfind("fuzz.nff:", 0) == 0);
        }
    }
    CHECK(errors > 0);
}

TEST_CASE("Triangulation of a concave polygon keeps area and orientation", "[nff]") {
    // An L shape (concave), counter-clockwise about +z; its first three vertices form a convex corner.
    std::vector<Vec3d> v = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    auto tris = triangulate(v);
    REQUIRE(tris.size() == 4);
    double area = 0;
    for (auto [a, b, c] : tris) {
        Vec3d n = cross(v[static_cast<std::size_t>(b)] - v[static_cast<std::size_t>(a)],
                        v[static_cast<std::size_t>(c)] - v[static_cast<std::size_t>(a)]);
        CHECK(n.z > 0);
        area += n.z / 2;
    }
    CHECK(area == Approx(3.0));
}
