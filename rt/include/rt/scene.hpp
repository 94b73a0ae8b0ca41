// Parsed NFF scene: plain records that keep their source location (the runtime shapes are built after).
#pragma once
#include "base/error.hpp"
#include "base/vec.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::rt {

using base::Vec3;
using base::Vec3d;
using base::Vec3f;
using base::SourceLoc;

// Malformed input: what() is "file:line:col: error: message".
class SceneError : public base::Error {
public:
    using base::Error::Error;
};

struct Color {
    float r = 0, g = 0, b = 0;
};

struct View {
    Vec3d from{0, 0, 1}, at{0, 0, 0}, up{0, 1, 0};
    double angle = 45;   // degrees, between the centres of the outermost pixel rows
    double hither = 0;   // recorded, not used (SPD: eye rays start at the eye)
    int width = 512, height = 512;
    SourceLoc loc;
};

struct Light {
    Vec3d pos;
    Color color{1, 1, 1};
    bool has_color = false;
    SourceLoc loc;
};

struct Material {
    Color color{1, 1, 1};
    double kd = 1, ks = 0, shine = 0, t = 0, ior = 1;
    SourceLoc loc;
};

// One `s`, `c`, `p` or `pp` entity; its position in Scene::entities is the primitive index.
struct Entity {
    enum class Kind : std::uint8_t { sphere, cylinder, cone, polygon, patch };
    Kind kind = Kind::sphere;
    int material = 0;
    SourceLoc loc;
    // sphere: centre = base, radius = base_r (negative: inside visible)
    // cylinder/cone: base, base_r, apex, apex_r (negative radii: inside visible)
    Vec3d base, apex;
    double base_r = 0, apex_r = 0;
    // polygon/patch: vertices (and patch normals), counter-clockwise seen from the front
    std::vector<Vec3d> verts;
    std::vector<Vec3d> normals;
};

struct Box {
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    void add(Vec3d p);
    void add(const Box& b);
    bool empty() const { return lo.x > hi.x; }
};

struct Scene {
    std::string name; // file name or built-in name
    View view;
    Color background{0, 0, 0};
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Entity> entities;
};

struct SceneCounts {
    std::size_t spheres = 0, cylinders = 0, cones = 0, polygons = 0, patches = 0;
    std::size_t triangles = 0;       // after triangulation of polygons and patches
    std::size_t reflective = 0, transmitting = 0; // entities by material
    std::size_t total() const { return spheres + cylinders + cones + polygons + patches; }
};

// Parse NFF text; `file` names it in diagnostics. Throws SceneError on malformed input.
Scene parse_nff(std::string_view text, const std::string& file);
// Read a file and parse it. Throws SceneError (also for an unreadable file).
Scene load_nff_file(const std::string& path);
// A file path or a built-in SPD name with optional size factor ("balls", "balls:2"). See spd.hpp.
Scene load_scene(const std::string& file_or_name);

SceneCounts count(const Scene& s);
Box entity_bounds(const Entity& e);
Box scene_bounds(const Scene& s);

// Triangulate a planar polygon (concave allowed, ear clipping) given CCW vertices; returns vertex
// index triples, counter-clockwise about the polygon's normal (v1-v0) x (v2-v1).
std::vector<std::array<int, 3>> triangulate(const std::vector<Vec3d>& verts);

} // namespace nesshi::rt
