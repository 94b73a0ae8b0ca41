// Shading with the SPD rules (the SC stage): surface point, lights with shadow rays, secondary rays.
//
// Shading is split in two so that the native renderer and the machine's SC stage run the same
// arithmetic in the same order (identical images, bit for bit):
//   plan_shade   at a hit: the surface, the ambient term, one shadow ray per light facing the
//                surface with the contribution it brings if unblocked, and the secondary rays;
//   finish_shade once every shadow ray's fate and the secondary rays' colours are known.
#pragma once
#include "kernels/abi.hpp"
#include "rt/render.hpp"

#include <cmath>
#include <vector>

namespace nesshi::rt {

struct Surface {
    Vec3f p;          // hit point
    Vec3f n;          // shading normal turned to face the incoming ray
    bool entering;    // the ray meets the visible (outside / front) side
    const Material* mat;
};

struct Col {
    float r = 0, g = 0, b = 0;
    Col& operator+=(Col o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
    bool operator==(const Col&) const = default;
};
inline Col scale(Col c, float s) { return {c.r * s, c.g * s, c.b * s}; }
inline Col to_col(Color c) { return {c.r, c.g, c.b}; }

Surface surface_at(const PreparedScene& prep, const Ray& ray, const Hit& hit);
// Per-light intensity and the ambient term: sqrt(L) / (2L) for L lights (SPD.md).
float light_intensity(std::size_t lights);
Ray reflection_ray(const Ray& in, const Surface& s, float eps);
// false on total internal reflection.
bool refraction_ray(const Ray& in, const Surface& s, float eps, Ray& out);

// The ABI's rule for ray directions: no 3DDDA value is NaN (kernels/abi.hpp).
using kernels::abi::flush_direction;

struct LightTerm {
    Ray shadow;          // toward the light
    Col diffuse;         // added when the shadow ray is not blocked
    bool has_spec = false;
    Col spec;            // added after `diffuse` when has_spec
};

struct ShadePlan {
    Col ambient;
    std::vector<LightTerm> lights; // lights facing the surface, in scene order
    bool reflect = false, refract = false;
    Ray reflect_ray, refract_ray;
    float ks = 0, kt = 0;
    float reflect_weight = 0, refract_weight = 0; // the secondary rays' contribution weights
};

// Counts shadow, reflection and refraction rays and total internal reflections into `rays`.
ShadePlan plan_shade(const PreparedScene& prep, const RenderOptions& opt, float intensity, const Ray& ray,
                     const Hit& hit, float weight, RayStats& rays);
// blocked[k]: the fate of plan.lights[k]; reflected/refracted: those rays' colours (ignored when
// the plan has no such ray).
Col finish_shade(const ShadePlan& plan, const std::vector<char>& blocked, Col reflected, Col refracted);

// Final pixels: the average of each pixel's four corner colours, clamped and rounded to bytes.
Image resolve_image(const std::vector<Col>& corners, int width, int height);

} // namespace nesshi::rt
