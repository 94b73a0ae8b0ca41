// Uniform grid builder: exact (padded) overlap tests, counting pass then fill pass.
#include "rt/grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace nesshi::rt {

void check_grid_resolution(int n) {
    if (n > kMaxGridResolution)
        throw std::invalid_argument(fmt::format("grid resolution is limited to {}", kMaxGridResolution));
}

int auto_grid_resolution(std::size_t shape_count) {
    double n = std::round(3.0 * std::cbrt(static_cast<double>(std::max<std::size_t>(shape_count, 1))));
    return static_cast<int>(std::clamp(n, 4.0, 100.0));
}

bool box_box_overlap(const Box& a, const Box& b) {
    for (int k = 0; k < 3; ++k)
        if (a.lo[k] > b.hi[k] || b.lo[k] > a.hi[k]) return false;
    return true;
}

bool sphere_box_overlap(Vec3d c, double r, const Box& b) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double e = 0;
        if (c[k] < b.lo[k]) e = b.lo[k] - c[k];
        else if (c[k] > b.hi[k]) e = c[k] - b.hi[k];
        d2 += e * e;
    }
    return d2 <= r * r;
}

// Separating-axis test (Akenine-Moeller): 3 box axes, the triangle normal, 9 edge cross products.
bool triangle_box_overlap(const std::array<Vec3d, 3>& tri, const Box& b) {
    Vec3d c = (b.lo + b.hi) * 0.5, h = (b.hi - b.lo) * 0.5;
    Vec3d v[3] = {tri[0] - c, tri[1] - c, tri[2] - c};
    for (int k = 0; k < 3; ++k) {
        double mn = std::min({v[0][k], v[1][k], v[2][k]}), mx = std::max({v[0][k], v[1][k], v[2][k]});
        if (mn > h[k] || mx < -h[k]) return false;
    }
    Vec3d e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    auto separated = [&](Vec3d axis) {
        double p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
        double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
        return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
    };
    if (separated(cross(e[0], e[1]))) return false;
    const Vec3d units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3d& u : units)
        for (const Vec3d& ed : e)
            if (separated(cross(u, ed))) return false;
    return true;
}

Box Grid::voxel_box(int ix, int iy, int iz) const {
    int i[3] = {ix, iy, iz};
    Box b;
    for (int k = 0; k < 3; ++k) {
        b.lo[k] = static_cast<double>(geom.lo[k]) + i[k] * static_cast<double>(geom.cell[k]);
        b.hi[k] = static_cast<double>(geom.lo[k]) + (i[k] + 1) * static_cast<double>(geom.cell[k]);
    }
    return b;
}

namespace {

// floor(q) as a voxel index clamped to 0..n-1, clamped before the conversion: a quotient beyond
// int's range, or NaN, would make the cast undefined.
int voxel_index(double q, int n) {
    const double f = std::floor(q);
    if (!(f > 0)) return 0;
    if (f >= n - 1) return n - 1;
    return static_cast<int>(f);
}

// The distance from |x| to the next binary32 value: the resolution of float coordinates near x.
double float_step(double x) {
    const float f = static_cast<float>(std::abs(x));
    return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) - static_cast<double>(f);
}

bool shape_overlaps(const Scene& scene, const ShapeSet& set, std::size_t si, const Box& vox) {
    const Shape& s = set.shapes[si];
    if (s.kind() == kShapeTriangle) return triangle_box_overlap(set.tri_verts[si], vox);
    const Entity& e = scene.entities[static_cast<std::size_t>(s.entity)];
    if (e.kind == Entity::Kind::sphere) return sphere_box_overlap(e.base, std::abs(e.base_r), vox);
    return box_box_overlap(set.bounds[si], vox); // cylinders, cones: tight box of the two end discs
}

} // namespace

Grid build_grid(const Scene& scene, const ShapeSet& set, int n) {
    auto t0 = std::chrono::steady_clock::now();
    Grid g;
    check_grid_resolution(n);
    if (n <= 0) n = auto_grid_resolution(set.shapes.size());
    Box box;
    for (const Box& b : set.bounds) box.add(b);
    if (box.empty()) box = Box{{-1, -1, -1}, {1, 1, 1}};
    double ext = std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z, 1e-6});
    double mag = std::max({std::abs(box.lo.x), std::abs(box.lo.y), std::abs(box.lo.z), std::abs(box.hi.x),
                           std::abs(box.hi.y), std::abs(box.hi.z)});
    // Pad the box so nothing lies on its faces, and the voxels in the overlap tests so that binary32
    // rounding in the traversal (a hit just past a voxel's exit) never loses a hit.
    double box_pad = 1e-4 * ext;
    box.lo = box.lo - Vec3d{box_pad, box_pad, box_pad};
    box.hi = box.hi + Vec3d{box_pad, box_pad, box_pad};
    // An axis that collapses in binary32 (the scene's extent there is below the float resolution
    // at its position: a unit sphere at x = 1e30) is widened around its centre to about two float
    // steps per cell; other axes, and every ordinary scene, are left exactly as they are.
    for (int k = 0; k < 3; ++k)
        if (!(static_cast<float>(box.hi[k]) > static_cast<float>(box.lo[k]))) {
            const double centre = 0.5 * (box.lo[k] + box.hi[k]);
            const double half = n * std::max(float_step(centre), float_step(box.lo[k]));
            box.lo[k] = std::min(box.lo[k], centre - half);
            box.hi[k] = std::max(box.hi[k], centre + half);
        }
    g.pad = 2e-5 * (ext + mag);
    g.box = box;
    for (int k = 0; k < 3; ++k) {
        g.geom.n[k] = n;
        g.geom.lo[k] = static_cast<float>(box.lo[k]);
        g.geom.hi[k] = static_cast<float>(box.hi[k]);
        double cell = (box.hi[k] - box.lo[k]) / n;
        g.geom.cell[k] = static_cast<float>(cell);
        g.geom.inv_cell[k] = static_cast<float>(1.0 / cell);
        g.stats.n[k] = n;
    }
    const std::size_t nv = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    std::vector<std::uint32_t> counts(nv, 0);
    auto range = [&](const Box& b, int lo[3], int hi[3]) {
        for (int k = 0; k < 3; ++k) {
            double c = g.geom.cell[k];
            lo[k] = voxel_index((b.lo[k] - g.pad - g.geom.lo[k]) / c, n);
            hi[k] = voxel_index((b.hi[k] + g.pad - g.geom.lo[k]) / c, n);
        }
    };
    auto for_each_voxel = [&](std::size_t si, auto&& fn) {
        int lo[3], hi[3];
        range(set.bounds[si], lo, hi);
        for (int iz = lo[2]; iz <= hi[2]; ++iz)
            for (int iy = lo[1]; iy <= hi[1]; ++iy)
                for (int ix = lo[0]; ix <= hi[0]; ++ix) {
                    Box vb = g.voxel_box(ix, iy, iz);
                    vb.lo = vb.lo - Vec3d{g.pad, g.pad, g.pad};
                    vb.hi = vb.hi + Vec3d{g.pad, g.pad, g.pad};
                    if (shape_overlaps(scene, set, si, vb))
                        fn((static_cast<std::size_t>(iz) * static_cast<std::size_t>(n) + static_cast<std::size_t>(iy)) *
                               static_cast<std::size_t>(n) +
                           static_cast<std::size_t>(ix));
                }
    };
    for (std::size_t si = 0; si < set.shapes.size(); ++si) for_each_voxel(si, [&](std::size_t v) { ++counts[v]; });
    g.offsets.assign(nv + 1, 0);
    for (std::size_t v = 0; v < nv; ++v) g.offsets[v + 1] = g.offsets[v] + counts[v];
    g.prims.assign(g.offsets[nv], 0);
    std::vector<std::uint32_t> fill(g.offsets.begin(), g.offsets.end() - 1);
    for (std::size_t si = 0; si < set.shapes.size(); ++si)
        for_each_voxel(si, [&](std::size_t v) { g.prims[fill[v]++] = static_cast<std::uint32_t>(si); });
    g.occupancy.assign(nv, 0);
    std::size_t empty = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        g.occupancy[v] = counts[v] ? 1 : 0;
        if (!counts[v]) ++empty;
    }
    g.stats.voxels = nv;
    g.stats.empty_voxels = empty;
    g.stats.references = g.prims.size();
    g.stats.refs_per_nonempty = nv > empty ? static_cast<double>(g.prims.size()) / static_cast<double>(nv - empty) : 0;
    g.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return g;
}

} // namespace nesshi::rt
