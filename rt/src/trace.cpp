// Closest-hit and any-hit queries: 3DDDA over the grid with the intersection twins per voxel.
#include "rt/trace.hpp"

#include "kernels/twins/dda.hpp"
#include "kernels/twins/quadric.hpp"
#include "kernels/twins/triangle.hpp"

#include <cstdint>
#include <span>

namespace nesshi::rt {

const char* ray_kind_name(RayKind k) {
    switch (k) {
    case RayKind::eye: return "eye";
    case RayKind::shadow: return "shadow";
    case RayKind::reflection: return "reflection";
    case RayKind::refraction: return "refraction";
    }
    return "?";
}

TraceCounters& TraceCounters::operator+=(const TraceCounters& o) {
    rays += o.rays;
    voxel_steps += o.voxel_steps;
    nonempty_voxels += o.nonempty_voxels;
    triangle_tests += o.triangle_tests;
    quadric_tests += o.quadric_tests;
    quadric_two_roots += o.quadric_two_roots;
    return *this;
}

Hit intersect_shape(const ShapeSet& set, std::size_t si, const Ray& ray) {
    const Shape& s = set.shapes[si];
    Hit h;
    if (s.kind() == kShapeTriangle) {
        kernels::twins::TriangleHit r = kernels::twins::intersect_triangle(s.w.data(), s.two_sided(), ray.o, ray.d, ray.tmin);
        if (r.hit) {
            h.hit = true;
            h.t = r.t;
            h.a = r.a;
            h.b = r.b;
        }
    } else {
        kernels::twins::QuadricHit r = kernels::twins::intersect_quadric(s.w.data(), s.two_sided(), ray.o, ray.d, ray.tmin);
        h.two_roots = r.two_roots;
        if (r.hit) {
            h.hit = true;
            h.t = r.t;
            h.front = r.front;
        }
    }
    if (h.hit) {
        h.shape = static_cast<std::int32_t>(si);
        h.entity = s.entity;
    }
    return h;
}

namespace {

inline void count_test(const ShapeSet& set, std::size_t si, TraceCounters& c) {
    if (set.shapes[si].kind() == kShapeTriangle) ++c.triangle_tests;
    else ++c.quadric_tests;
}

} // namespace

VoxelWalk::VoxelWalk(const Grid& grid, const Ray& ray) : grid_(&grid) {
    live_ = kernels::twins::dda_setup(grid.geom, ray.o, ray.d, ray.tmin, ray.tmax, s_);
}

bool VoxelWalk::next(VoxelSpan& span, TraceCounters& c) {
    while (live_) {
        if (!first_ && !kernels::twins::dda_step(s_)) {
            live_ = false;
            break;
        }
        first_ = false;
        ++c.voxel_steps;
        if (grid_->occupancy[static_cast<std::size_t>(s_.addr)]) {
            ++c.nonempty_voxels;
            span = {s_.addr, s_.t_in, s_.voxel_exit()};
            return true;
        }
    }
    return false;
}

namespace {

// The shapes listed in the voxel a span crosses.
std::span<const std::uint32_t> voxel_shapes(const Grid& grid, const VoxelSpan& span) {
    const auto addr = static_cast<std::size_t>(span.addr);
    return {grid.prims.data() + grid.offsets[addr], grid.prims.data() + grid.offsets[addr + 1]};
}

// One ray-shape test, counted.
Hit test_shape(const ShapeSet& set, std::uint32_t shape, const Ray& ray, TraceCounters& c) {
    count_test(set, shape, c);
    const Hit h = intersect_shape(set, shape, ray);
    c.quadric_two_roots += h.two_roots;
    return h;
}

} // namespace

bool intersect_voxel_nearest(const Grid& grid, const ShapeSet& set, const Ray& ray, const VoxelSpan& span, Hit& best,
                             TraceCounters& c) {
    for (const std::uint32_t shape : voxel_shapes(grid, span)) {
        const Hit h = test_shape(set, shape, ray, c);
        if (!h.hit || !(h.t <= span.t_out) || !(h.t < ray.tmax)) continue;
        if (h.t < best.t || (h.t == best.t && h.shape < best.shape)) best = h;
    }
    return best.hit;
}

bool intersect_voxel_any(const Grid& grid, const ShapeSet& set, const Ray& ray, const VoxelSpan& span,
                         TraceCounters& c) {
    for (const std::uint32_t shape : voxel_shapes(grid, span)) {
        const Hit h = test_shape(set, shape, ray, c);
        if (h.hit && h.t < ray.tmax) return true;
    }
    return false;
}

Hit nearest_hit(const Grid& grid, const ShapeSet& set, const Ray& ray, TraceCounters& c) {
    ++c.rays;
    Hit best;
    VoxelWalk walk(grid, ray);
    VoxelSpan span;
    while (walk.next(span, c))
        if (intersect_voxel_nearest(grid, set, ray, span, best, c)) break;
    return best;
}

bool any_hit(const Grid& grid, const ShapeSet& set, const Ray& ray, TraceCounters& c) {
    ++c.rays;
    VoxelWalk walk(grid, ray);
    VoxelSpan span;
    while (walk.next(span, c))
        if (intersect_voxel_any(grid, set, ray, span, c)) return true;
    return false;
}

Hit nearest_hit_brute(const ShapeSet& set, const Ray& ray, TraceCounters& c) {
    ++c.rays;
    Hit best;
    for (std::size_t si = 0; si < set.shapes.size(); ++si) {
        count_test(set, si, c);
        Hit h = intersect_shape(set, si, ray);
        c.quadric_two_roots += h.two_roots;
        if (!h.hit || !(h.t < ray.tmax)) continue;
        if (h.t < best.t) best = h; // ascending shape order: a tie keeps the lower index
    }
    return best;
}

bool any_hit_brute(const ShapeSet& set, const Ray& ray, TraceCounters& c) {
    ++c.rays;
    for (std::size_t si = 0; si < set.shapes.size(); ++si) {
        count_test(set, si, c);
        Hit h = intersect_shape(set, si, ray);
        c.quadric_two_roots += h.two_roots;
        if (h.hit && h.t < ray.tmax) return true;
    }
    return false;
}

} // namespace nesshi::rt
