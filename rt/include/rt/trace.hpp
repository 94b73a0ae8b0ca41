// Ray record and the closest-hit / any-hit queries: grid (3DDDA + twins) and brute force.
#pragma once
#include "rt/grid.hpp"
#include "rt/shapes.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <limits>

namespace nesshi::rt {

enum class RayKind : std::uint8_t { eye = 0, shadow = 1, reflection = 2, refraction = 3 };
inline constexpr int kRayKinds = 4;
const char* ray_kind_name(RayKind k);

// The ray as the stages see it: origin, unit direction, the open interval (tmin, tmax) of accepted hits.
struct Ray {
    Vec3f o, d;
    float tmin = 0.0f;
    float tmax = std::numeric_limits<float>::infinity();
    RayKind kind = RayKind::eye;
    int depth = 1; // eye ray = 1 (SPD rule 7)
};

struct Hit {
    bool hit = false;
    float t = std::numeric_limits<float>::infinity();
    std::int32_t shape = -1;  // index into ShapeSet::shapes
    std::int32_t entity = -1; // NFF primitive index
    float a = 0, b = 0;       // triangle weights of e1, e2 (for patch normals)
    bool front = true;        // quadric: hit on the visible/outside root
    bool two_roots = false;   // quadric: the quadratic had two distinct real roots (hit or not)
};

struct TraceCounters {
    std::uint64_t rays = 0;
    std::uint64_t voxel_steps = 0;      // voxels visited by the 3DDDA (OS loop iterations + 1 per ray)
    std::uint64_t nonempty_voxels = 0;  // visits that went to intersection (OS -> IC)
    std::uint64_t triangle_tests = 0;
    std::uint64_t quadric_tests = 0;
    std::uint64_t quadric_two_roots = 0; // quadric tests whose quadratic had two distinct real roots
    TraceCounters& operator+=(const TraceCounters& o);
};

// The OS stage as an iterator: walks the grid with the 3DDDA twin and yields each non-empty voxel
// with its t-span. Every voxel visited counts one voxel step.
struct VoxelSpan {
    int addr = 0;     // voxel address (iz*ny + iy)*nx + ix
    float t_in = 0;   // where the ray enters the voxel
    float t_out = 0;  // where it leaves it (clamped to the ray's tmax and the grid box)
};

class VoxelWalk {
public:
    VoxelWalk(const Grid& grid, const Ray& ray);
    bool next(VoxelSpan& span, TraceCounters& c);

private:
    const Grid* grid_;
    kernels::twins::DdaState s_{};
    bool live_ = false, first_ = true;
};

// The IC stage for one voxel: the nearest hit among its primitives with t <= span.t_out, merged into
// `best` (an exact tie goes to the lower shape index); true when `best` now holds a hit.
bool intersect_voxel_nearest(const Grid& grid, const ShapeSet& set, const Ray& ray, const VoxelSpan& span, Hit& best,
                             TraceCounters& c);
// Any hit among the voxel's primitives with t < ray.tmax (shadow rays).
bool intersect_voxel_any(const Grid& grid, const ShapeSet& set, const Ray& ray, const VoxelSpan& span,
                         TraceCounters& c);

// Nearest hit with t in (tmin, tmax); an exact tie goes to the lower shape (= entity) index.
Hit nearest_hit(const Grid& grid, const ShapeSet& set, const Ray& ray, TraceCounters& c);
// Any hit with t in (tmin, tmax): shadow rays.
bool any_hit(const Grid& grid, const ShapeSet& set, const Ray& ray, TraceCounters& c);
// References without the grid: every shape tested.
Hit nearest_hit_brute(const ShapeSet& set, const Ray& ray, TraceCounters& c);
bool any_hit_brute(const ShapeSet& set, const Ray& ray, TraceCounters& c);

// One intersection test of the twins (triangle or quadric record), t > tmin.
Hit intersect_shape(const ShapeSet& set, std::size_t shape, const Ray& ray);

} // namespace nesshi::rt

template <>
struct fmt::formatter<nesshi::base::Vec3f> : fmt::formatter<float> {
    auto format(const nesshi::base::Vec3f& v, fmt::format_context& ctx) const {
        return fmt::format_to(ctx.out(), "({:g} {:g} {:g})", v.x, v.y, v.z);
    }
};

template <>
struct fmt::formatter<nesshi::rt::Ray> : fmt::formatter<float> {
    auto format(const nesshi::rt::Ray& r, fmt::format_context& ctx) const {
        return fmt::format_to(ctx.out(), "{} ray depth {} o {} d {} t ({:g}, {:g})", nesshi::rt::ray_kind_name(r.kind),
                              r.depth, r.o, r.d, r.tmin, r.tmax);
    }
};

template <>
struct fmt::formatter<nesshi::rt::Hit> : fmt::formatter<float> {
    auto format(const nesshi::rt::Hit& h, fmt::format_context& ctx) const {
        if (!h.hit) return fmt::format_to(ctx.out(), "miss");
        return fmt::format_to(ctx.out(), "hit primitive {} (shape {}) t {:g}", h.entity, h.shape, h.t);
    }
};
