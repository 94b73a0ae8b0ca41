// Our implementations of the SPD generators balls, mount, rings, tetra and tree (Haines' SPD 3.14),
// reproducing the default NFF output (curved primitives) of the public-domain originals.
#include "spd_gen.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace nesshi::rt {

namespace {

constexpr double kPi = std::numbers::pi;

// 4x4 matrix used with row vectors (p' = p M), as the SPD library does.
struct Mat4 {
    double m[4][4] = {};
    static Mat4 identity() {
        Mat4 r;
        for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
        return r;
    }
};

Mat4 mul(const Mat4& a, const Mat4& b) {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j] + a.m[i][3] * b.m[3][j];
    return r;
}

enum Axis { kX, kY, kZ };

Mat4 rotate(Axis axis, double angle) {
    Mat4 r;
    const double c = std::cos(angle), s = std::sin(angle);
    switch (axis) {
    case kX:
        r.m[0][0] = 1;
        r.m[1][1] = c;
        r.m[2][2] = c;
        r.m[1][2] = s;
        r.m[2][1] = -s;
        break;
    case kY:
        r.m[1][1] = 1;
        r.m[0][0] = c;
        r.m[2][2] = c;
        r.m[2][0] = s;
        r.m[0][2] = -s;
        break;
    case kZ:
        r.m[2][2] = 1;
        r.m[0][0] = c;
        r.m[1][1] = c;
        r.m[0][1] = s;
        r.m[1][0] = -s;
        break;
    }
    r.m[3][3] = 1;
    return r;
}

// Rotation by `angle` about the unit vector `a`.
Mat4 rotate_about(Vec3d a, double angle) {
    const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
    Mat4 r;
    r.m[0][0] = a.x * a.x + (1.0 - a.x * a.x) * c;
    r.m[0][1] = a.x * a.y * t + a.z * s;
    r.m[0][2] = a.x * a.z * t - a.y * s;
    r.m[1][0] = a.x * a.y * t - a.z * s;
    r.m[1][1] = a.y * a.y + (1.0 - a.y * a.y) * c;
    r.m[1][2] = a.y * a.z * t + a.x * s;
    r.m[2][0] = a.x * a.z * t + a.y * s;
    r.m[2][1] = a.y * a.z * t - a.x * s;
    r.m[2][2] = a.z * a.z + (1.0 - a.z * a.z) * c;
    r.m[3][3] = 1;
    return r;
}

Vec3d xform_vector(Vec3d v, const Mat4& m) {
    return {v.x * m.m[0][0] + v.y * m.m[1][0] + v.z * m.m[2][0], v.x * m.m[0][1] + v.y * m.m[1][1] + v.z * m.m[2][1],
            v.x * m.m[0][2] + v.y * m.m[1][2] + v.z * m.m[2][2]};
}
Vec3d xform_point(Vec3d v, const Mat4& m) { return xform_vector(v, m) + Vec3d{m.m[3][0], m.m[3][1], m.m[3][2]}; }

Vec3d unit(Vec3d v) {
    double l = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return {v.x / l, v.y / l, v.z / l};
}

// The SPD surface description: highlight half-angle `ang` (degrees) becomes a Phong exponent.
void material(NffWriter& w, Vec3d color, double kd, double ks, double ang, double kt, double ior) {
    const double rad = kPi * ang / 180.0;
    double phong = rad <= 0.0 ? 100000.0 : (rad >= kPi / 2.0 ? 1.0 : std::log(0.5) / std::log(std::cos(rad)));
    w.material(color.x, color.y, color.z, kd, ks, phong, kt, ior);
}

void header(NffWriter& w, Vec3d from, Vec3d at, Vec3d up, double hither) {
    w.background(0.078, 0.361, 0.753);
    w.view(from, at, up, 45.0, hither, 512);
}

void check_size(int size, int lo, int hi, const char* name) {
    if (size < lo || size > hi)
        throw std::invalid_argument(fmt::format("{}: size factor {} out of range [{}, {}]", name, size, lo, hi));
}

// ---- balls (sphereflake) ----

struct Balls {
    NffWriter& w;
    std::array<Vec3d, 9> objset;

    explicit Balls(NffWriter& out) : w(out) {
        const double d = 1.0 / std::sqrt(2.0);
        std::array<Vec3d, 3> trio = {Vec3d{d, d, 0}, Vec3d{d, 0, -d}, Vec3d{0, d, -d}};
        Mat4 m = rotate_about(unit({1, -1, 0}), std::asin(2.0 / std::sqrt(6.0)));
        for (Vec3d& t : trio) t = xform_vector(t, m);
        for (int set = 0; set < 3; ++set) {
            Mat4 rz = rotate(kZ, set * 2.0 * kPi / 3.0);
            for (int v = 0; v < 3; ++v) objset[static_cast<std::size_t>(set * 3 + v)] = xform_vector(trio[static_cast<std::size_t>(v)], rz);
        }
    }

    // center/radius of this sphere; dir = direction from the parent (unit-ish), ratio = child/parent radius
    void object(int depth, Vec3d center, double radius, Vec3d dir, double ratio) {
        w.sphere(center, radius);
        if (depth <= 0) return;
        --depth;
        Mat4 m;
        if (dir.z >= 0.9999) m = Mat4::identity();
        else if (dir.z <= -0.9999) m = rotate(kY, kPi);
        else m = rotate_about(unit(cross(Vec3d{0, 0, 1}, dir)), std::acos(dir.z));
        const double scale = radius * (1.0 + ratio);
        for (const Vec3d& o : objset) {
            Vec3d c = xform_vector(o, m);
            c = {c.x * scale + center.x, c.y * scale + center.y, c.z * scale + center.z};
            Vec3d cd = c - center;
            cd = {cd.x / scale, cd.y / scale, cd.z / scale};
            object(depth, c, radius * ratio, cd, ratio);
        }
    }
};

// ---- mount (fractal mountain, Carpenter's method; the original hash for the published database) ----

double gauss_rand(long seed) {
    long ix1 = 0, ix2 = seed;
    double v1 = 0, r = 0;
    do {
        ix1 = (28411 + ix2 * 8121) % 134456;
        ix2 = (28411 + ix1 * 8121) % 134456;
        v1 = ix1 * 2.0 / 134456.0 - 1.0;
        const double v2 = ix2 * 2.0 / 134456.0 - 1.0;
        r = v1 * v1 + v2 * v2;
    } while (r >= 1.0);
    return v1 * std::sqrt(-2.0 * std::log(r) / r);
}

struct Mount {
    NffWriter& w;
    int size;
    double roughness;

    long hash(long a, long b) const {
        const unsigned long ua = static_cast<unsigned long>(a), ub = static_cast<unsigned long>(b);
        const int c = size;
        return static_cast<long>(((ua << (23 - c)) + (ub << (15 - c)) + (ua << (7 - c))) & 0xffffUL);
    }
    double rnd(long a, long b) const { return gauss_rand(21 + hash(a, b)); }

    void grow(double npts, int width, int llx, int lly, double ll, double lr, double ur, double ul) {
        if (width == 1) {
            const double lx = -1.0 + llx * 2.0 / npts, rx = -1.0 + (llx + 1) * 2.0 / npts;
            const double ly = -1.0 + lly * 2.0 / npts, uy = -1.0 + (lly + 1) * 2.0 / npts;
            const Vec3d corner[4] = {{lx, ly, ll}, {rx, ly, lr}, {rx, uy, ur}, {lx, uy, ul}};
            for (int tri = 0; tri < 2; ++tri) {
                Vec3d t[3];
                for (int v = 0; v < 3; ++v) t[v] = corner[(v + tri * 2) % 4];
                w.polygon(t, t + 3);
            }
            return;
        }
        const int half = width >> 1;
        const double rise = half * 2.0 / npts * roughness;
        const double lower = (ll + lr) / 2.0 + rise * rnd(llx + half, lly);
        const double right = (lr + ur) / 2.0 + rise * rnd(llx + width, lly + half);
        const double upper = (ur + ul) / 2.0 + rise * rnd(llx + half, lly + width);
        const double left = (ul + ll) / 2.0 + rise * rnd(llx, lly + half);
        const double middle = (ll + lr + ur + ul) / 4.0 + 1.4142136 * rise * rnd(llx + half, lly + half);
        grow(npts, half, llx, lly, ll, lower, middle, left);
        grow(npts, half, llx + half, lly, lower, lr, right, middle);
        grow(npts, half, llx + half, lly + half, middle, right, ur, upper);
        grow(npts, half, llx, lly + half, left, middle, upper, ul);
    }
};

// Glass-sphere pyramid of mount: one sphere on top, three below it.
void mount_spheres(NffWriter& w, Vec3d center, double r) {
    const Vec3d pt{0, 0, r * std::sqrt(3.0 / 2.0)};
    w.sphere(center + pt, r);
    const Vec3d np = xform_vector(pt, rotate_about(unit({1, 1, 0}), std::acos(-1.0 / 3.0)));
    for (int i = 0; i < 3; ++i) w.sphere(xform_vector(np, rotate(kZ, i * 2.0 * kPi / 3.0)) + center, r);
}

// ---- tetra ----

void tetra(NffWriter& w, int depth, Vec3d c, double r) {
    if (depth <= 1) {
        Vec3d pt[4];
        int n = 0;
        for (int x = -1; x <= 1; x += 2)
            for (int y = -1; y <= 1; y += 2)
                for (int z = -1; z <= 1; z += 2)
                    if (x * y * z == 1) pt[n++] = {c.x + x * r, c.y + y * r, c.z + z * r};
        for (int face = 0; face < 4; ++face) {
            int ord[3] = {face % 4, (face + 1) % 4, (face + 2) % 4};
            if (face % 2 == 1) std::swap(ord[0], ord[2]);
            Vec3d f[3] = {pt[ord[0]], pt[ord[1]], pt[ord[2]]};
            w.polygon(f, f + 3);
        }
        return;
    }
    for (int x = -1; x <= 1; x += 2)
        for (int y = -1; y <= 1; y += 2)
            for (int z = -1; z <= 1; z += 2)
                if (x * y * z == 1) tetra(w, depth - 1, {c.x + x * r / 2.0, c.y + y * r / 2.0, c.z + z * r / 2.0}, r / 2.0);
}

// ---- tree (Aono & Kunii) ----

struct Tree {
    NffWriter& w;
    Mat4 branch[2];

    explicit Tree(NffWriter& out) : w(out) {
        const double angle[2] = {40.0, 25.0}, diverge[2] = {90.0, 140.0 + 90.0}, contr[2] = {0.65, 0.70};
        for (int i = 0; i < 2; ++i) {
            Mat4 r = mul(rotate(kX, angle[i] * kPi / 180.0), rotate(kZ, diverge[i] * kPi / 180.0));
            Mat4 st = Mat4::identity();
            st.m[0][0] = st.m[1][1] = st.m[2][2] = contr[i];
            st.m[3][2] = 1.0;
            branch[i] = mul(r, st);
        }
    }
    void grow(const Mat4& m, double scale, int depth) {
        const Vec3d base = xform_point({0, 0, 0}, m), apex = xform_point({0, 0, 1}, m);
        const double br = scale * 0.15, ar = br * 0.67;
        w.cone(base, br, apex, ar);
        w.sphere(apex, ar);
        if (depth <= 0) return;
        for (const Mat4& b : branch) grow(mul(b, m), scale * 0.67, depth - 1);
    }
};

// ---- gears ----

constexpr int kTeeth = 36;

void gear_tooth(double gear_angle, double tooth_angle, Vec3d center, Vec3d outer, Vec3d inner, Vec3d* edge) {
    edge[0] = xform_vector(outer, rotate(kZ, gear_angle - 0.19 * tooth_angle)) + center;
    edge[1] = xform_vector(outer, rotate(kZ, gear_angle + 0.19 * tooth_angle)) + center;
    edge[2] = xform_vector(inner, rotate(kZ, gear_angle + 0.3 * tooth_angle)) + center;
    edge[3] = xform_vector(inner, rotate(kZ, gear_angle + 0.7 * tooth_angle)) + center;
}

// One gear: the top face (a concave 144-gon), 144 side rectangles, the bottom face.
void gear(NffWriter& w, Vec3d center, double offset_angle, double outer_r, double inner_r, double thickness) {
    Vec3d outer{outer_r, 0, 0}, inner{inner_r, 0, 0};
    const double tooth = 2.0 * kPi / kTeeth;
    Vec3d pts[4 * kTeeth];
    for (int t = 0; t < kTeeth; ++t)
        gear_tooth(offset_angle + 2.0 * kPi * t / kTeeth, tooth, center, outer, inner, &pts[t * 4]);
    w.polygon(pts, pts + 4 * kTeeth);
    for (int side = 0; side < 4 * kTeeth; ++side) {
        const int next = (side + 1) % (4 * kTeeth);
        Vec3d q[4] = {pts[side], pts[side], pts[next], pts[next]};
        q[1].z -= thickness;
        q[2].z -= thickness;
        w.polygon(q, q + 4);
    }
    outer.z = inner.z = -thickness;
    for (int t = 0; t < kTeeth; ++t)
        gear_tooth(offset_angle - 2.0 * kPi * t / kTeeth, -tooth, center, outer, inner, &pts[t * 4]);
    w.polygon(pts, pts + 4 * kTeeth);
}

} // namespace

void gen_gears(NffWriter& w, int size) {
    check_size(size, 1, 8, "gears");
    header(w, {-1.1, -2.1, 2.6}, {0, 0, 0}, {0, 0, 1}, 1.0);
    for (Vec3d l : {Vec3d{2, 4, 4}, Vec3d{-2, 4, 3}, Vec3d{2, -2.5, 2.5}, Vec3d{-1, -4, 2}, Vec3d{-1.111, -2.121, 2.626}})
        w.light(l);
    material(w, {1.0, 0.85, 0.7}, 0.3, 0.6, 37.0, 0.0, 0.0);
    const Vec3d ground[4] = {{2, 2, 0}, {-2, 2, 0}, {-2, -2, 0}, {2, -2, 0}};
    w.polygon(ground, ground + 4);
    const double edge_diff = 1.0 - 0.9;
    const double outer_r = 1.0 / (static_cast<double>(size) - static_cast<double>(size - 1) * edge_diff / 2.0);
    const Vec3d zero{-1.0 + outer_r, -1.0 + outer_r, 1.0};
    const Vec3d off{outer_r * (2.0 - edge_diff), outer_r * (2.0 - edge_diff), -1.0 / static_cast<double>(size)};
    auto frac = [](double x) { return x - static_cast<double>(static_cast<long>(x)); };
    for (int iz = 0; iz < size; ++iz)
        for (int iy = 0; iy < size; ++iy)
            for (int ix = 0; ix < size; ++ix) {
                const Vec3d c{zero.x + ix * off.x, zero.y + iy * off.y, zero.z + iz * off.z};
                Vec3d col{0.01 + frac((ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0), 0.01 + frac((iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0),
                          0.01 + frac((iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0)};
                const double m = std::max(std::max(col.x, col.y), col.z);
                col = {col.x / m, col.y / m, col.z / m};
                if ((ix * 4 + iy * 2 + iz) % 5 == 0) material(w, col, 0.2, 0.0, 0.0, 0.8, 1.1);
                else material(w, col, 1.0, 0.0, 0.0, 0.0, 0.0);
                const double angle = kPi * static_cast<double>((ix + iy + iz) % 2) / kTeeth;
                const double thickness = std::min(0.1, 1.0 / (2.0 * size));
                gear(w, c, angle, 0.995 * outer_r, (1.0 - edge_diff) * outer_r, thickness);
            }
}

void gen_balls(NffWriter& w, int size) {
    check_size(size, 1, 6, "balls");
    header(w, {2.1, 1.3, 1.7}, {0, 0, 0}, {0, 0, 1}, 0.01);
    for (Vec3d l : {Vec3d{4, 3, 2}, Vec3d{1, -4, 4}, Vec3d{-3, 1, 5}}) w.light(l);
    material(w, {1.0, 0.75, 0.33}, 0.8, 0.0, 0.0, 0.0, 1.0);
    const Vec3d floor[4] = {{12, 12, -0.5}, {-12, 12, -0.5}, {-12, -12, -0.5}, {12, -12, -0.5}};
    w.polygon(floor, floor + 4);
    material(w, {1.0, 0.9, 0.7}, 0.5, 0.5, 37.0, 0.0, 1.0);
    Balls b(w);
    b.object(size, {0, 0, 0}, 0.5, {0, 0, 1}, 1.0 / 3.0);
}

void gen_mount(NffWriter& w, int size) {
    check_size(size, 1, 7, "mount"); // the original hash shifts by 7 - size
    header(w, {-1.6, 1.6, 1.7}, {0, 0, 0}, {0, 0, 1}, 0.01);
    w.light({-100, -100, 100});
    material(w, {1, 1, 1}, 0.1, 0.1, 6.7, 0.9, 1.5);
    mount_spheres(w, {-0.8, 0.8, 1.0}, 0.17);
    material(w, {0.5, 0.45, 0.35}, 1.0, 0.0, 0.0, 0.0, 0.0);
    const int n = 1 << size;
    const double ratio = 2.0 / std::exp(std::log(2.0) / (2.2 - 1.0));
    Mount m{w, size, std::sqrt(ratio * ratio - 1.0)};
    m.grow(static_cast<double>(n), n, 0, 0, 0.0, 0.0, 0.0, 0.0);
}

void gen_rings(NffWriter& w, int size) {
    check_size(size, 1, 20, "rings");
    const double radius = 0.07412;
    const double spread = 1.0 / std::sin(kPi / 8.0);
    const double y_diff = spread, xz_diff = 1.0; // SPREAD_OUT = 1 <= spread
    const Vec3d from{-1.0, -spread, 0.5};
    header(w, from, {from.x, from.y + 1.0, from.z}, {0, 0, 1}, 1.0);
    for (Vec3d l : {Vec3d{3, -spread, 3}, Vec3d{-4, -spread, 1}, Vec3d{2, -spread, -4}}) w.light(l);
    material(w, {1, 1, 1}, 1.0, 0.0, 0.0, 0.0, 0.0);
    const double wy = y_diff * (size + 1);
    const double wxz = 1.01 * (wy - from.y) * std::tan(kPi / 8.0);
    const Vec3d wall[4] = {{wxz + from.x, wy, wxz + from.z},
                           {-wxz + from.x, wy, wxz + from.z},
                           {-wxz + from.x, wy, -wxz + from.z},
                           {wxz + from.x, wy, -wxz + from.z}};
    w.polygon(wall, wall + 4);
    const Vec3d colors[6] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}};
    // 30 points: six pentagons through the edge midpoints of a dodecahedron.
    Vec3d dodec[30];
    const double scale = 1.0 / (1.0 + radius);
    for (int v = 0; v < 5; ++v) dodec[v] = {scale * std::cos(v * 2.0 * kPi / 5.0), scale * std::sin(v * 2.0 * kPi / 5.0), 0.0};
    const Mat4 xm = rotate(kX, 2.0 * std::acos(std::cos(kPi / 3.0) / std::sin(kPi / 5.0)));
    for (int p = 1; p < 6; ++p) {
        const Mat4 zm = rotate(kZ, kPi * (2.0 * (p - 1) + 1.0) / 5.0);
        for (int v = 0; v < 5; ++v) dodec[5 * p + v] = xform_point(xform_point(dodec[v], xm), zm);
    }
    for (int depth = 0; depth < size; ++depth) {
        Vec3d off;
        off.y = y_diff * (depth + 1);
        for (int oz = 0; oz <= depth; ++oz) {
            off.z = xz_diff * (2 * oz - depth);
            for (int ox = 0; ox <= depth; ++ox) {
                off.x = xz_diff * (2 * ox - depth);
                for (int e = 0; e < 30; ++e) {
                    int prev = e - 1;
                    if (e % 5 == 0) {
                        prev = e + 4;
                        material(w, colors[e / 5], 0.5, 0.2, 37.0, 0.0, 0.0);
                    }
                    const Vec3d base = dodec[e] + off, apex = dodec[prev] + off;
                    w.cone(base, radius, apex, radius);
                    w.sphere(base, radius);
                }
            }
        }
    }
}

void gen_tetra(NffWriter& w, int size) {
    check_size(size, 1, 10, "tetra");
    header(w, {1.022846, -3.177154, -2.174512}, {-0.004103, -0.004103, 0.216539}, {-0.816497, -0.816497, 0.816497}, 1.0);
    w.light({2, -18, -5});
    material(w, {1.0, 0.2, 0.2}, 1.0, 0.0, 0.0, 0.0, 0.0);
    tetra(w, size, {0, 0, 0}, 1.0);
}

void gen_tree(NffWriter& w, int size) {
    check_size(size, 1, 16, "tree");
    header(w, {4.5, 0.4, 2.0}, {0, 0, 1.5}, {0, 0, 1}, 1.0);
    for (Vec3d l : {Vec3d{-5, 5, 50}, Vec3d{30, -30, 30}, Vec3d{-40, -30, 20}, Vec3d{10, 30, 40}, Vec3d{-30, 40, 10},
                    Vec3d{50, 25, 20}, Vec3d{-10, -60, 30}})
        w.light(l);
    material(w, {0.2, 0.7, 0.2}, 1.0, 0.0, 0.0, 0.0, 0.0);
    const Vec3d field[4] = {{50, 50, 0}, {-50, 50, 0}, {-50, -50, 0}, {50, -50, 0}};
    w.polygon(field, field + 4);
    material(w, {0.55, 0.4, 0.2}, 1.0, 0.0, 0.0, 0.0, 0.0);
    Tree t(w);
    t.grow(Mat4::identity(), 1.0, size);
}

} // namespace nesshi::rt
