// Native twin of the IC quadric kernel (sphere, cylinder, cone): the assembly kernels mirror this.
//
// Works on the quadric record of shapes.hpp: local origin o' = o - c, Q in the paper's 10-coefficient
// form stored as the symmetric matrix M = [A D/2 F/2; D/2 B E/2; F/2 E/2 C], g/2 = (G/2, H/2, I/2), J.
// With the ray o' + t d:  Q = a t^2 + 2 b t + c, where
//   a = d.(M d),  b = d.(M o' + g/2),  c = o'.(M o' + g/2) + (g/2).o' + J.
// The root where Q' = 2(a t + b) = -2 sqrt(b^2 - a c) < 0 is the front (outside) face, whatever
// the sign of a: t_front = (-b - s)/a, t_back = (s - b)/a. One-sided primitives take only t_front;
// two-sided (transmitting) ones the nearer valid root. A root counts when t > tmin and its axial
// coordinate h = a.o' + t (a.d) lies in [0, L] (spheres: a = 0, L = 0, always true).
// Operations, in order (binary32, no FMA):
//   o' = o - c                                            3 add
//   Md  (x, y, z rows: (m0*dx + m1*dy) + m2*dz)           9 mul 6 add
//   Mo  (rows: ((m0*ox + m1*oy) + m2*oz) + g/2)           9 mul 9 add
//   a = (dx*Mdx + dy*Mdy) + dz*Mdz                        3 mul 2 add
//   b = (dx*Mox + dy*Moy) + dz*Moz                        3 mul 2 add
//   c = (((ox*Mox + oy*Moy) + oz*Moz) + ((Gh*ox + Hh*oy) + Ih*oz)) + J    6 mul 6 add
//   disc = b*b - a*c                                      2 mul 1 add, compare disc >= 0
//   s = sqrt(disc); nb = -b                               1 sqrt 1 neg
//   tf = (nb - s)/a; tb = (nb + s)/a                      2 add 2 div
//   ao = (ax*ox + ay*oy) + az*oz; ad = (ax*dx + ay*dy) + az*dz   6 mul 4 add
//   hf = ao + tf*ad; hb = ao + tb*ad                      2 mul 2 add
//   valid_f = tf > tmin && hf >= 0 && hf <= L; valid_b likewise and two-sided   7 compares
//   pick: valid_f && (!valid_b || tf <= tb) ? tf : tb      1 compare, selects
// Total about 40 mul, 37 add, 2 div, 1 sqrt, 1 neg, 9 compares. A ray with a = 0 (parallel to a
// cylinder's axis) gives inf/NaN roots: no hit. Returns the hit t and whether it was the front root.
#pragma once
#include "rt/vec.hpp"

#include <cmath>

namespace nesshi::rt::twins {

struct QuadricHit {
    float t;
    bool hit;
    bool front; // true: hit from outside (the outward normal faces the ray)
};

inline QuadricHit intersect_quadric(const float* w, bool two_sided, Vec3f o, Vec3f d, float tmin) {
    const float ox = o.x - w[0], oy = o.y - w[1], oz = o.z - w[2];
    const float A = w[3], B = w[4], C = w[5], Dh = w[6], Eh = w[7], Fh = w[8];
    const float Gh = w[9], Hh = w[10], Ih = w[11], J = w[12];
    const float mdx = (A * d.x + Dh * d.y) + Fh * d.z;
    const float mdy = (Dh * d.x + B * d.y) + Eh * d.z;
    const float mdz = (Fh * d.x + Eh * d.y) + C * d.z;
    const float mox = ((A * ox + Dh * oy) + Fh * oz) + Gh;
    const float moy = ((Dh * ox + B * oy) + Eh * oz) + Hh;
    const float moz = ((Fh * ox + Eh * oy) + C * oz) + Ih;
    const float qa = (d.x * mdx + d.y * mdy) + d.z * mdz;
    const float qb = (d.x * mox + d.y * moy) + d.z * moz;
    const float qc = (((ox * mox + oy * moy) + oz * moz) + ((Gh * ox + Hh * oy) + Ih * oz)) + J;
    const float disc = qb * qb - qa * qc;
    if (!(disc >= 0.0f)) return {0.0f, false, false};
    const float s = std::sqrt(disc);
    const float nb = -qb;
    const float tf = (nb - s) / qa;
    const float tb = (nb + s) / qa;
    const float ao = (w[13] * ox + w[14] * oy) + w[15] * oz;
    const float ad = (w[13] * d.x + w[14] * d.y) + w[15] * d.z;
    const float hf = ao + tf * ad;
    const float hb = ao + tb * ad;
    const float L = w[16];
    const bool vf = tf > tmin && hf >= 0.0f && hf <= L;
    const bool vb = two_sided && tb > tmin && hb >= 0.0f && hb <= L;
    if (vf && (!vb || tf <= tb)) return {tf, true, true};
    if (vb) return {tb, true, false};
    return {0.0f, false, false};
}

} // namespace nesshi::rt::twins
