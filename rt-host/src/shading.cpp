// SC-stage helpers: surface normal at a hit, light intensity, reflection and refraction rays.
#include "rt/shading.hpp"

#include <cmath>

namespace nesshi::rt {

Surface surface_at(const PreparedScene& prep, const Ray& ray, const Hit& hit) {
    const Shape& s = prep.shapes.shapes[static_cast<std::size_t>(hit.shape)];
    const ShadeRecord& sh = prep.shapes.shade[static_cast<std::size_t>(hit.shape)];
    Surface out;
    out.p = ray.o + ray.d * hit.t;
    out.mat = &prep.scene.materials[static_cast<std::size_t>(sh.material)];
    Vec3f n;
    if (s.kind() == kShapeTriangle) {
        out.entering = dot(sh.normal, ray.d) < 0.0f;
        if (sh.smooth) {
            const float w0 = 1.0f - hit.a - hit.b;
            n = normalize(sh.n0 * w0 + sh.n1 * hit.a + sh.n2 * hit.b);
        } else {
            n = sh.normal;
        }
    } else {
        // Gradient of Q at the local point: 2 (M p + g/2); points to the visible side.
        const float* w = s.w.data();
        const Vec3f q = out.p - Vec3f{w[0], w[1], w[2]};
        n = normalize(Vec3f{(w[3] * q.x + w[6] * q.y) + w[8] * q.z + w[9],
                            (w[6] * q.x + w[4] * q.y) + w[7] * q.z + w[10],
                            (w[8] * q.x + w[7] * q.y) + w[5] * q.z + w[11]});
        out.entering = hit.front;
    }
    out.n = dot(n, ray.d) < 0.0f ? n : -n;
    return out;
}

float light_intensity(std::size_t lights) {
    const float l = static_cast<float>(lights ? lights : 1);
    return std::sqrt(l) / (2.0f * l);
}

Ray reflection_ray(const Ray& in, const Surface& s, float eps) {
    Ray r;
    r.o = s.p;
    r.d = normalize(in.d - s.n * (2.0f * dot(in.d, s.n)));
    r.tmin = eps;
    r.kind = RayKind::reflection;
    r.depth = in.depth + 1;
    return r;
}

bool refraction_ray(const Ray& in, const Surface& s, float eps, Ray& out) {
    const float ior = static_cast<float>(s.mat->ior);
    const float eta = s.entering ? 1.0f / ior : ior;
    const float cosi = -dot(in.d, s.n);
    const float k = 1.0f - eta * eta * (1.0f - cosi * cosi);
    if (k < 0.0f) return false;
    out.o = s.p;
    out.d = normalize(in.d * eta + s.n * (eta * cosi - std::sqrt(k)));
    out.tmin = eps;
    out.kind = RayKind::refraction;
    out.depth = in.depth + 1;
    return true;
}

} // namespace nesshi::rt
