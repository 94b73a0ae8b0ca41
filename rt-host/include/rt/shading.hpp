// Shading with the SPD rules (the SC stage): surface point, lights with shadow rays, secondary rays.
#pragma once
#include "rt/render.hpp"

namespace nesshi::rt {

struct Surface {
    Vec3f p;          // hit point
    Vec3f n;          // shading normal turned to face the incoming ray
    bool entering;    // the ray meets the visible (outside / front) side
    const Material* mat;
};

Surface surface_at(const PreparedScene& prep, const Ray& ray, const Hit& hit);
// Per-light intensity and the ambient term: sqrt(L) / (2L) for L lights (SPD.md).
float light_intensity(std::size_t lights);
Ray reflection_ray(const Ray& in, const Surface& s, float eps);
// false on total internal reflection.
bool refraction_ray(const Ray& in, const Surface& s, float eps, Ray& out);

} // namespace nesshi::rt
