// Eye-ray generation (see camera.hpp for the exact operation order).
#include "rt/camera.hpp"
#include "rt/shading.hpp"

#include <cmath>
#include <numbers>

namespace nesshi::rt {

Camera::Camera(const View& v, int w, int h) : width(w), height(h) {
    Vec3d fwd = normalize(v.at - v.from);
    Vec3d right = normalize(cross(fwd, v.up));
    Vec3d up = cross(right, fwd);
    eye = to_float(v.from);
    this->fwd = to_float(fwd);
    this->right = to_float(right);
    this->up = to_float(up);
    double s = std::tan(v.angle * std::numbers::pi / 360.0) * (w > 1 ? static_cast<double>(w) / (w - 1) : 1.0);
    su = static_cast<float>(s);
    sv = static_cast<float>(s * h / w);
}

Ray Camera::eye_ray(int i, int j) const {
    const float u = (static_cast<float>(2 * i) / static_cast<float>(width) - 1.0f) * su;
    const float v = (1.0f - static_cast<float>(2 * j) / static_cast<float>(height)) * sv;
    Vec3f d = (fwd + right * u) + up * v;
    const float inv = 1.0f / std::sqrt(dot(d, d));
    Ray r;
    r.o = eye;
    r.d = flush_direction(d * inv);
    r.tmin = 0.0f;
    r.kind = RayKind::eye;
    r.depth = 1;
    return r;
}

} // namespace nesshi::rt
