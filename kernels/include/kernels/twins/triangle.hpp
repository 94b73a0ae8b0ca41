// Native twin of the IC triangle kernel: the assembly kernels mirror this operation order exactly.
//
// Plane-equation method on the 12-word triangle record of shapes.hpp. Binary32 only, no FMA
// (the build uses -ffp-contract=off). Operations, in order:
//   dn = (R2x*dx + R2y*dy) + R2z*dz                     3 mul 2 add
//   on = ((R2x*ox + R2y*oy) + R2z*oz) + w2               3 mul 3 add
//   t  = (-on) / dn                                      1 neg 1 div
//   p  = o + t*d  (x, y, z)                              3 mul 3 add
//   a  = ((R0x*px + R0y*py) + R0z*pz) + w0               3 mul 3 add
//   b  = ((R1x*px + R1y*py) + R1z*pz) + w1               3 mul 3 add
//   s  = a + b                                           1 add
//   hit = face && t > tmin && a >= 0 && b >= 0 && s <= 1 6 compares (face: dn < 0, or dn != 0 two-sided)
// Total: 15 mul, 15 add, 1 neg, 1 div, 6 compares = 38 operations. The caller compares t with its
// t-range (t <= voxel exit, t < best). A ray parallel to the plane gives t = inf or NaN: no hit.
#pragma once
#include "base/vec.hpp"

namespace nesshi::kernels::twins {

using base::Vec3;
using base::Vec3d;
using base::Vec3f;


struct TriangleHit {
    float t, a, b;
    bool hit;
};

inline TriangleHit intersect_triangle(const float* w, bool two_sided, Vec3f o, Vec3f d, float tmin) {
    const float dn = (w[0] * d.x + w[1] * d.y) + w[2] * d.z;
    const float on = ((w[0] * o.x + w[1] * o.y) + w[2] * o.z) + w[3];
    const float t = (-on) / dn;
    const float px = o.x + t * d.x;
    const float py = o.y + t * d.y;
    const float pz = o.z + t * d.z;
    const float a = ((w[4] * px + w[5] * py) + w[6] * pz) + w[7];
    const float b = ((w[8] * px + w[9] * py) + w[10] * pz) + w[11];
    const float s = a + b;
    const bool face = two_sided ? (dn != 0.0f) : (dn < 0.0f);
    const bool hit = face && t > tmin && a >= 0.0f && b >= 0.0f && s <= 1.0f;
    return {t, a, b, hit};
}

} // namespace nesshi::kernels::twins
