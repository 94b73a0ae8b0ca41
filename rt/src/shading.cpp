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
    r.d = flush_direction(normalize(in.d - s.n * (2.0f * dot(in.d, s.n))));
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
    out.d = flush_direction(normalize(in.d * eta + s.n * (eta * cosi - std::sqrt(k))));
    out.tmin = eps;
    out.kind = RayKind::refraction;
    out.depth = in.depth + 1;
    return true;
}

ShadePlan plan_shade(const PreparedScene& prep, const RenderOptions& opt, float intensity, const Ray& ray,
                     const Hit& hit, float weight, RayStats& rays) {
    const Surface s = surface_at(prep, ray, hit);
    const Material& m = *s.mat;
    const Col base = to_col(m.color);
    const float kd = static_cast<float>(m.kd), ks = static_cast<float>(m.ks), kt = static_cast<float>(m.t);
    ShadePlan plan;
    plan.ks = ks;
    plan.kt = kt;
    plan.ambient = scale(base, kd * intensity);
    const Vec3f refl = normalize(ray.d - s.n * (2.0f * dot(ray.d, s.n)));
    for (const Light& l : prep.scene.lights) {
        const Vec3f lp = to_float(l.pos);
        const Vec3f ld = lp - s.p;
        const float dist = length(ld);
        const Vec3f dir = ld * (1.0f / dist);
        const float ndl = dot(s.n, dir);
        if (!(ndl > 0.0f)) continue; // SPD rule 10: no shadow ray toward a light behind the surface
        LightTerm t;
        t.shadow.o = s.p;
        t.shadow.d = flush_direction(dir);
        t.shadow.tmin = opt.epsilon;
        t.shadow.tmax = dist;
        t.shadow.kind = RayKind::shadow;
        t.shadow.depth = ray.depth + 1;
        ++rays.shadow_rays;
        const Col lc = l.has_color ? to_col(l.color) : Col{1, 1, 1};
        t.diffuse = scale(Col{base.r * lc.r, base.g * lc.g, base.b * lc.b}, kd * ndl * intensity);
        if (ks > 0.0f) {
            const float rl = dot(refl, dir);
            if (rl > 0.0f) {
                t.has_spec = true;
                t.spec = scale(lc, ks * intensity * std::pow(rl, static_cast<float>(m.shine)));
            }
        }
        plan.lights.push_back(t);
    }
    if (ray.depth >= opt.max_depth) return plan;
    if (ks > 0.0f || kt > 0.0f) {
        if (!(opt.cutoff > 0 && weight * ks < opt.cutoff)) {
            ++rays.reflection_rays;
            plan.reflect = true;
            plan.reflect_ray = reflection_ray(ray, s, opt.epsilon);
            plan.reflect_weight = weight * ks;
        }
    }
    if (kt > 0.0f) {
        Ray rr;
        if (!refraction_ray(ray, s, opt.epsilon, rr)) {
            ++rays.total_internal_reflections;
        } else if (!(opt.cutoff > 0 && weight * kt < opt.cutoff)) {
            ++rays.refraction_rays;
            plan.refract = true;
            plan.refract_ray = rr;
            plan.refract_weight = weight * kt;
        }
    }
    return plan;
}

Col finish_shade(const ShadePlan& plan, const std::vector<char>& blocked, Col reflected, Col refracted) {
    Col c = plan.ambient;
    for (std::size_t k = 0; k < plan.lights.size(); ++k) {
        if (blocked[k]) continue;
        c += plan.lights[k].diffuse;
        if (plan.lights[k].has_spec) c += plan.lights[k].spec;
    }
    if (plan.reflect) c += scale(reflected, plan.ks);
    if (plan.refract) c += scale(refracted, plan.kt);
    return c;
}

namespace {
std::uint8_t to_byte(float v) {
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; // NaN -> 0
    return static_cast<std::uint8_t>(static_cast<int>(v * 255.0f + 0.5f));
}
} // namespace

Image resolve_image(const std::vector<Col>& corners, int W, int H) {
    const std::size_t cw = static_cast<std::size_t>(W) + 1;
    Image img;
    img.width = W;
    img.height = H;
    img.rgb.resize(static_cast<std::size_t>(W) * static_cast<std::size_t>(H) * 3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t a = static_cast<std::size_t>(y) * cw + static_cast<std::size_t>(x);
            Col c = corners[a];
            c += corners[a + 1];
            c += corners[a + cw];
            c += corners[a + cw + 1];
            std::uint8_t* px = &img.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)) * 3];
            px[0] = to_byte(c.r * 0.25f);
            px[1] = to_byte(c.g * 0.25f);
            px[2] = to_byte(c.b * 0.25f);
        }
    return img;
}

} // namespace nesshi::rt
