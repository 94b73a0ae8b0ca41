// Eye rays through the pixel corners, per the SPD conventions of SPD.md.
//
// fwd = normalize(at - from), right = normalize(fwd x up), up' = right x fwd (double, set-up time,
// rounded to binary32). s = tan(angle/2) * W/(W-1). Corner (i, j), i = 0..W, j = 0..H (binary32):
//   u = (float(2i)/float(W) - 1) * s;  v = (1 - float(2j)/float(H)) * sv   (sv = s*H/W)
//   d = (fwd + right*u) + up'*v;  d = d * (1/sqrt(d.d))
#pragma once
#include "rt/scene.hpp"
#include "rt/trace.hpp"

namespace nesshi::rt {

struct Camera {
    Vec3f eye, fwd, right, up;
    float su = 1, sv = 1;
    int width = 512, height = 512;

    Camera() = default;
    Camera(const View& v, int width, int height);
    Ray eye_ray(int i, int j) const; // corner i in [0, W], j in [0, H]
};

} // namespace nesshi::rt
