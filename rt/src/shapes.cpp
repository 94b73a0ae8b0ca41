// Builds the IC shape records (shapes.hpp) from the parsed scene, in double, rounded once to binary32.
#include "rt/shapes.hpp"

#include <cmath>
#include <limits>

namespace nesshi::rt {

namespace {

// double -> binary32 without undefined behaviour: out-of-range values saturate to +-inf.
float to_f(double v) {
    constexpr double big = static_cast<double>(std::numeric_limits<float>::max());
    if (v > big) return std::numeric_limits<float>::infinity();
    if (v < -big) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(v); // NaN converts to NaN
}

void set_triangle_weights(Shape& s, Vec3d v0, Vec3d v1, Vec3d v2) {
    Vec3d e1 = v1 - v0, e2 = v2 - v0, n = cross(e1, e2);
    // Inverse of the column matrix [e1 e2 n]: rows are (e2 x n, n x e1, e1 x e2) / det.
    double det = dot(e1, cross(e2, n));
    Vec3d r0 = cross(e2, n) * (1.0 / det);
    Vec3d r1 = cross(n, e1) * (1.0 / det);
    Vec3d r2 = n * (1.0 / det);
    auto put = [&](int at, Vec3d r) {
        s.w[static_cast<std::size_t>(at)] = to_f(r.x);
        s.w[static_cast<std::size_t>(at + 1)] = to_f(r.y);
        s.w[static_cast<std::size_t>(at + 2)] = to_f(r.z);
        s.w[static_cast<std::size_t>(at + 3)] = to_f(-dot(r, v0));
    };
    put(0, r2);
    put(4, r0);
    put(8, r1);
}

// M = sign * (I - (1 + k^2) a a^T), g = sign * (-2 r0 k a), J = sign * (-r0^2), local to `origin`.
void set_quadric(Shape& s, Vec3d origin, Vec3d axis, double r0, double k, double len, double sign) {
    double f = 1.0 + k * k;
    double m[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = sign * ((i == j ? 1.0 : 0.0) - f * axis[i] * axis[j]);
    Vec3d gh = axis * (sign * (-r0 * k));
    double J = sign * (-r0 * r0);
    double vals[18] = {origin.x, origin.y, origin.z, m[0][0], m[1][1], m[2][2], m[0][1], m[1][2], m[0][2],
                       gh.x,     gh.y,     gh.z,     J,       axis.x,  axis.y,  axis.z,  len,     0.0};
    for (std::size_t i = 0; i < 18; ++i) s.w[i] = to_f(vals[i]);
}

} // namespace

Shape triangle_record(Vec3d v0, Vec3d v1, Vec3d v2, bool two_sided) {
    Shape s;
    s.kind_flags = kShapeTriangle | (two_sided ? kShapeTwoSided : 0u);
    set_triangle_weights(s, v0, v1, v2);
    return s;
}

ShapeSet build_shapes(const Scene& scene) {
    ShapeSet out;
    for (std::size_t ei = 0; ei < scene.entities.size(); ++ei) {
        const Entity& e = scene.entities[ei];
        const Material& mat = scene.materials[static_cast<std::size_t>(e.material)];
        const bool transmit = mat.t > 0;
        Shape s;
        s.entity = static_cast<std::int32_t>(ei);
        ShadeRecord sh;
        sh.material = e.material;
        switch (e.kind) {
        case Entity::Kind::sphere: {
            s.kind_flags = kShapeQuadric | (transmit ? kShapeTwoSided : 0u);
            double r = std::abs(e.base_r);
            set_quadric(s, e.base, {0, 0, 0}, r, 0.0, 0.0, e.base_r < 0 ? -1.0 : 1.0);
            s.w[3] = s.w[4] = s.w[5] = e.base_r < 0 ? -1.0f : 1.0f;
            s.w[6] = s.w[7] = s.w[8] = 0.0f;
            out.shapes.push_back(s);
            out.shade.push_back(sh);
            out.bounds.push_back(entity_bounds(e));
            out.tri_verts.push_back({});
            break;
        }
        case Entity::Kind::cylinder:
        case Entity::Kind::cone: {
            s.kind_flags = kShapeQuadric | (transmit ? kShapeTwoSided : 0u);
            Vec3d ax = e.apex - e.base;
            double len = length(ax);
            ax = ax * (1.0 / len);
            double r0 = std::abs(e.base_r), r1 = std::abs(e.apex_r);
            bool inside = e.base_r < 0 || e.apex_r < 0;
            set_quadric(s, e.base, ax, r0, (r1 - r0) / len, len, inside ? -1.0 : 1.0);
            out.shapes.push_back(s);
            out.shade.push_back(sh);
            out.bounds.push_back(entity_bounds(e));
            out.tri_verts.push_back({});
            break;
        }
        case Entity::Kind::polygon:
        case Entity::Kind::patch: {
            const bool patch = e.kind == Entity::Kind::patch;
            s.kind_flags = kShapeTriangle | ((transmit || patch) ? kShapeTwoSided : 0u);
            for (auto [i0, i1, i2] : triangulate(e.verts)) {
                auto u = [&](int i) { return e.verts[static_cast<std::size_t>(i)]; };
                Shape t = s;
                set_triangle_weights(t, u(i0), u(i1), u(i2));
                ShadeRecord ts = sh;
                ts.normal = to_float(normalize(cross(u(i1) - u(i0), u(i2) - u(i0))));
                if (patch) {
                    auto nn = [&](int i) { return to_float(e.normals[static_cast<std::size_t>(i)]); };
                    ts.smooth = 1;
                    ts.n0 = nn(i0);
                    ts.n1 = nn(i1);
                    ts.n2 = nn(i2);
                }
                Box b;
                b.add(u(i0));
                b.add(u(i1));
                b.add(u(i2));
                out.shapes.push_back(t);
                out.shade.push_back(ts);
                out.bounds.push_back(b);
                out.tri_verts.push_back({u(i0), u(i1), u(i2)});
            }
            break;
        }
        }
    }
    return out;
}

} // namespace nesshi::rt
