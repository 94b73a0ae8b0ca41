// Shape records: what IC memory holds per primitive (20 words); rt/shapes.hpp builds them.
//
// IC memory layout of one record (all 32-bit words, little-endian):
//   word 0      kind and flags: bits 0-1 kind (0 triangle, 1 quadric), bit 8 two-sided
//   word 1      NFF entity index (int32; the primitive index reported for hits)
//   words 2-19  payload (binary32), see below
// Triangle payload (plane-equation method, the paper's "(alpha, beta, gamma) from a 3x3 inverse"):
//   w[0..3]   R2, w2: c = R2.p + w2 is the signed plane coordinate, R2 = n/|n|^2 with n = e1 x e2
//   w[4..7]   R0, w0: a = R0.p + w0 (weight of e1 = v1 - v0)
//   w[8..11]  R1, w1: b = R1.p + w1 (weight of e2 = v2 - v0)
//   w[12..17] unused (0)
//   where [R0; R1; R2] is the inverse of the column matrix [e1 e2 n] and wi = -Ri.v0.
// Quadric payload (sphere, cylinder, cone in the paper's form, local to a point c):
//   w[0..2]   c: local coordinates are p - c
//   w[3..12]  A B C D/2 E/2 F/2 G/2 H/2 I/2 J:
//             Q(x,y,z) = A x^2 + B y^2 + C z^2 + D xy + E yz + F zx + G x + H y + I z + J, Q < 0 inside
//             (for inside-visible primitives, negative radii, Q is negated)
//   w[13..15] unit axis a (zero for a sphere)
//   w[16]     length L: a hit at local p counts when 0 <= a.p <= L (a sphere has a = 0, L = 0)
//   w[17]     unused (0)
#pragma once

#include <array>
#include <cstdint>

namespace nesshi::kernels {

inline constexpr int kShapeWords = 20;
inline constexpr std::uint32_t kShapeTriangle = 0;
inline constexpr std::uint32_t kShapeQuadric = 1;
inline constexpr std::uint32_t kShapeTwoSided = 1u << 8;

struct Shape {
    std::uint32_t kind_flags = 0;
    std::int32_t entity = -1;
    std::array<float, 18> w{};

    std::uint32_t kind() const { return kind_flags & 3u; }
    bool two_sided() const { return (kind_flags & kShapeTwoSided) != 0; }
};
static_assert(sizeof(Shape) == kShapeWords * 4, "a shape record is 20 words");

} // namespace nesshi::kernels
