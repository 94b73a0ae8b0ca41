// Native twin of the IC quadric kernel (sphere, cylinder, cone): the assembly kernels mirror this.
//
// Works on the quadric record of shapes.hpp: local origin o' = o - c, Q in the paper's 10-coefficient
// form stored as the symmetric matrix M = [A D/2 F/2; D/2 B E/2; F/2 E/2 C], g/2 = (G/2, H/2, I/2), J.
// Precision: the ray origin is first moved along the ray to the point nearest c (t0 = -(o'.d), d is a
// unit vector), so the quadratic is solved with an origin at the primitive's scale instead of the
// eye's distance (in binary32, |o'|^2 - r^2 for a small far sphere would lose r^2 entirely).
// With the ray q + s d, q = o' + t0 d, t = t0 + s:  Q = a s^2 + 2 b s + c, where
//   a = d.(M d),  b = d.(M q + g/2),  c = q.(M q + g/2) + (g/2).q + J.
// The root where Q' = 2(a s + b) = -2 sqrt(b^2 - a c) < 0 is the front (outside) face, whatever
// the sign of a: s_front = (-b - r)/a, s_back = (r - b)/a, r = sqrt(b^2 - a c). One-sided
// primitives take only the front root; two-sided (transmitting) ones the nearer valid root. A root
// counts when t > tmin and its axial coordinate h = a.q + s (a.d) lies in [0, L] (spheres: a = 0, L = 0).
// Operations, in order (binary32, no FMA):
//   o' = o - c                                            3 add
//   t0 = -((o'x*dx + o'y*dy) + o'z*dz)                    3 mul 2 add 1 neg
//   q = o' + t0*d                                         3 mul 3 add
//   Md  (rows: (m0*dx + m1*dy) + m2*dz)                   9 mul 6 add
//   Mq  (rows: ((m0*qx + m1*qy) + m2*qz) + g/2)           9 mul 9 add
//   a = (dx*Mdx + dy*Mdy) + dz*Mdz                        3 mul 2 add
//   b = (dx*Mqx + dy*Mqy) + dz*Mqz                        3 mul 2 add
//   c = (((qx*Mqx + qy*Mqy) + qz*Mqz) + ((Gh*qx + Hh*qy) + Ih*qz)) + J    6 mul 6 add
//   disc = b*b - a*c                                      2 mul 1 add, compare disc >= 0
//   r = sqrt(disc); nb = -b                               1 sqrt 1 neg
//   sf = (nb - r)/a; sb = (nb + r)/a                      2 add 2 div
//   tf = t0 + sf; tb = t0 + sb                            2 add
//   aq = (ax*qx + ay*qy) + az*qz; ad = (ax*dx + ay*dy) + az*dz   6 mul 4 add
//   hf = aq + sf*ad; hb = aq + sb*ad                      2 mul 2 add
//   valid_f = tf > tmin && hf >= 0 && hf <= L; valid_b likewise and two-sided   7 compares
//   pick: valid_f && (!valid_b || tf <= tb) ? tf : tb      1 compare, selects
// Total 46 mul, 44 add, 2 neg, 2 div, 1 sqrt, 9 compares. A ray with a = 0 (parallel to a
// cylinder's axis) gives inf/NaN roots: no hit. Returns the hit t and whether it was the front root.
#pragma once
#include "base/vec.hpp"

#include <cmath>

namespace nesshi::kernels::twins {

using base::Vec3;
using base::Vec3d;
using base::Vec3f;


struct QuadricHit {
    float t;
    bool hit;
    bool front; // true: hit from outside (the outward normal faces the ray)
    // The quadratic had two distinct real roots (disc > 0), hit or not: the paper prices a quadric
    // test at 50 cycles only then, so the gap analysis counts such tests apart.
    bool two_roots = false;
};

inline QuadricHit intersect_quadric(const float* w, bool two_sided, Vec3f o, Vec3f d, float tmin) {
    const float px = o.x - w[0], py = o.y - w[1], pz = o.z - w[2];
    const float t0 = -((px * d.x + py * d.y) + pz * d.z);
    const float qx = px + t0 * d.x, qy = py + t0 * d.y, qz = pz + t0 * d.z;
    const float A = w[3], B = w[4], C = w[5], Dh = w[6], Eh = w[7], Fh = w[8];
    const float Gh = w[9], Hh = w[10], Ih = w[11], J = w[12];
    const float mdx = (A * d.x + Dh * d.y) + Fh * d.z;
    const float mdy = (Dh * d.x + B * d.y) + Eh * d.z;
    const float mdz = (Fh * d.x + Eh * d.y) + C * d.z;
    const float mqx = ((A * qx + Dh * qy) + Fh * qz) + Gh;
    const float mqy = ((Dh * qx + B * qy) + Eh * qz) + Hh;
    const float mqz = ((Fh * qx + Eh * qy) + C * qz) + Ih;
    const float qa = (d.x * mdx + d.y * mdy) + d.z * mdz;
    const float qb = (d.x * mqx + d.y * mqy) + d.z * mqz;
    const float qc = (((qx * mqx + qy * mqy) + qz * mqz) + ((Gh * qx + Hh * qy) + Ih * qz)) + J;
    const float disc = qb * qb - qa * qc;
    if (!(disc >= 0.0f)) return {0.0f, false, false};
    const float r = std::sqrt(disc);
    const float nb = -qb;
    const float sf = (nb - r) / qa;
    const float sb = (nb + r) / qa;
    const float tf = t0 + sf;
    const float tb = t0 + sb;
    const float aq = (w[13] * qx + w[14] * qy) + w[15] * qz;
    const float ad = (w[13] * d.x + w[14] * d.y) + w[15] * d.z;
    const float hf = aq + sf * ad;
    const float hb = aq + sb * ad;
    const float L = w[16];
    const bool vf = tf > tmin && hf >= 0.0f && hf <= L;
    const bool vb = two_sided && tb > tmin && hb >= 0.0f && hb <= L;
    const bool two = disc > 0.0f;
    if (vf && (!vb || tf <= tb)) return {tf, true, true, two};
    if (vb) return {tb, true, false, two};
    return {0.0f, false, false, two};
}

} // namespace nesshi::kernels::twins
