// Shapes of a scene: one IC shape record (kernels/shape_record.hpp, the layout) per triangle or
// quadric, and the SC shading records beside them.
#pragma once
#include "kernels/shape_record.hpp"
#include "rt/scene.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace nesshi::rt {

using kernels::kShapeQuadric;
using kernels::kShapeTriangle;
using kernels::kShapeTwoSided;
using kernels::kShapeWords;
using kernels::Shape;

// What SC memory holds per shape for shading (not used by the intersection kernels).
struct ShadeRecord {
    std::int32_t material = 0;
    std::int32_t smooth = 0;   // 1: patch, interpolate n0..n2 with the hit's (a, b)
    Vec3f n0, n1, n2;          // patch vertex normals
    Vec3f normal;              // triangle front normal (unit)
};

struct ShapeSet {
    std::vector<Shape> shapes;        // IC shape records, in entity order
    std::vector<ShadeRecord> shade;   // parallel to shapes
    std::vector<Box> bounds;          // exact bounds (double) of each shape, for the grid
    std::vector<std::array<Vec3d, 3>> tri_verts; // triangle vertices (double); zero for quadrics
};

// Triangulates polygons and patches and builds one record per triangle or quadric.
ShapeSet build_shapes(const Scene& scene);

// Triangle v0 v1 v2 as its shape record (kernels/shape_record.hpp): the plane equations of the
// rows of [e1 e2 n]^-1, computed in double and rounded once; entity -1. Shared by build_shapes,
// the kernel report's workloads and the kernel tests.
Shape triangle_record(Vec3d v0, Vec3d v1, Vec3d v2, bool two_sided);

} // namespace nesshi::rt
