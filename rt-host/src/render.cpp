// The native renderer: corner rows spread over threads, Whitted tracing with the SPD rules.
#include "rt/render.hpp"
#include "rt/shading.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

namespace nesshi::rt {

RayStats& RayStats::operator+=(const RayStats& o) {
    eye_rays += o.eye_rays;
    eye_rays_hit += o.eye_rays_hit;
    shadow_rays += o.shadow_rays;
    shadow_rays_blocked += o.shadow_rays_blocked;
    reflection_rays += o.reflection_rays;
    refraction_rays += o.refraction_rays;
    secondary_rays_hit += o.secondary_rays_hit;
    total_internal_reflections += o.total_internal_reflections;
    return *this;
}

PreparedScene prepare(Scene scene, int grid_n) {
    auto t0 = std::chrono::steady_clock::now();
    PreparedScene p;
    p.scene = std::move(scene);
    p.shapes = build_shapes(p.scene);
    if (grid_n <= 0) grid_n = choose_grid_resolution(p.scene, p.shapes).n;
    p.grid = build_grid(p.scene, p.shapes, grid_n);
    p.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return p;
}

GridChoice choose_grid_resolution(const Scene& scene, const ShapeSet& shapes) {
    GridChoice choice;
    double best = 0;
    PreparedScene p;
    p.scene = scene;
    p.shapes = shapes;
    RenderOptions o;
    o.width = o.height = 64;
    o.threads = 0;
    for (int n : {20, 35, 50, 70, 100}) {
        p.grid = build_grid(p.scene, p.shapes, n);
        const RenderResult r = render_native(p, o);
        double cost = 0;
        for (const TraceCounters& c : r.stats.traversal)
            cost += 11.0 * static_cast<double>(c.voxel_steps) + 40.0 * static_cast<double>(c.triangle_tests) +
                    50.0 * static_cast<double>(c.quadric_tests);
        choice.costs.emplace_back(n, cost);
        if (choice.n == 0 || cost < best) {
            best = cost;
            choice.n = n;
        }
    }
    return choice;
}

namespace {

struct Col {
    float r = 0, g = 0, b = 0;
    Col& operator+=(Col o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
};
Col scale(Col c, float s) { return {c.r * s, c.g * s, c.b * s}; }
Col from(Color c) { return {c.r, c.g, c.b}; }

struct Tracer {
    const PreparedScene& prep;
    const RenderOptions& opt;
    float intensity;
    RayStats rays;
    std::array<TraceCounters, kRayKinds> trav{};

    Col trace(const Ray& ray, float weight, Hit* first) {
        TraceCounters& tc = trav[static_cast<std::size_t>(ray.kind)];
        Hit hit = opt.brute_force ? nearest_hit_brute(prep.shapes, ray, tc) : nearest_hit(prep.grid, prep.shapes, ray, tc);
        if (first) *first = hit;
        if (!hit.hit) return from(prep.scene.background);
        if (ray.kind == RayKind::eye) ++rays.eye_rays_hit;
        else ++rays.secondary_rays_hit;
        return shade(ray, hit, weight);
    }

    Col shade(const Ray& ray, const Hit& hit, float weight) {
        const Surface s = surface_at(prep, ray, hit);
        const Material& m = *s.mat;
        const Col base = from(m.color);
        const float kd = static_cast<float>(m.kd), ks = static_cast<float>(m.ks), kt = static_cast<float>(m.t);
        Col c = scale(base, kd * intensity); // ambient
        const Vec3f refl = normalize(ray.d - s.n * (2.0f * dot(ray.d, s.n)));
        for (const Light& l : prep.scene.lights) {
            const Vec3f lp = to_float(l.pos);
            const Vec3f ld = lp - s.p;
            const float dist = length(ld);
            const Vec3f dir = ld * (1.0f / dist);
            const float ndl = dot(s.n, dir);
            if (!(ndl > 0.0f)) continue; // SPD rule 10: no shadow ray toward a light behind the surface
            Ray sr;
            sr.o = s.p;
            sr.d = dir;
            sr.tmin = opt.epsilon;
            sr.tmax = dist;
            sr.kind = RayKind::shadow;
            sr.depth = ray.depth + 1;
            ++rays.shadow_rays;
            TraceCounters& sc = trav[static_cast<std::size_t>(RayKind::shadow)];
            if (opt.brute_force ? any_hit_brute(prep.shapes, sr, sc) : any_hit(prep.grid, prep.shapes, sr, sc)) {
                ++rays.shadow_rays_blocked;
                continue;
            }
            const Col lc = l.has_color ? from(l.color) : Col{1, 1, 1};
            c += scale(Col{base.r * lc.r, base.g * lc.g, base.b * lc.b}, kd * ndl * intensity);
            if (ks > 0.0f) {
                const float rl = dot(refl, dir);
                if (rl > 0.0f) c += scale(lc, ks * intensity * std::pow(rl, static_cast<float>(m.shine)));
            }
        }
        if (ray.depth >= opt.max_depth) return c;
        if (ks > 0.0f || kt > 0.0f) {
            if (!(opt.cutoff > 0 && weight * ks < opt.cutoff)) {
                ++rays.reflection_rays;
                c += scale(trace(reflection_ray(ray, s, opt.epsilon), weight * ks, nullptr), ks);
            }
        }
        if (kt > 0.0f) {
            Ray rr;
            if (!refraction_ray(ray, s, opt.epsilon, rr)) {
                ++rays.total_internal_reflections;
            } else if (!(opt.cutoff > 0 && weight * kt < opt.cutoff)) {
                ++rays.refraction_rays;
                c += scale(trace(rr, weight * kt, nullptr), kt);
            }
        }
        return c;
    }
};

std::uint8_t to_byte(float v) {
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; // NaN -> 0
    return static_cast<std::uint8_t>(static_cast<int>(v * 255.0f + 0.5f));
}

} // namespace

RenderResult render_native(const PreparedScene& prep, const RenderOptions& opt) {
    const int W = opt.width, H = opt.height;
    const std::size_t cw = static_cast<std::size_t>(W) + 1, ch = static_cast<std::size_t>(H) + 1;
    Camera cam(prep.scene.view, W, H);
    RenderResult res;
    std::vector<Col> corners(cw * ch);
    if (opt.id_buffer) res.id_buffer.assign(cw * ch, -1);
    if (opt.t_buffer) res.t_buffer.assign(cw * ch, -1.0f);
    int threads = opt.threads > 0 ? opt.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::min<int>(threads, static_cast<int>(ch));
    std::vector<RayStats> row_rays(ch);
    std::vector<std::array<TraceCounters, kRayKinds>> row_trav(ch);
    std::atomic<int> next_row{0}, rows_done{0};
    const float intensity = light_intensity(prep.scene.lights.size());

    auto worker = [&] {
        for (;;) {
            const int j = next_row.fetch_add(1);
            if (j >= static_cast<int>(ch)) return;
            Tracer tr{prep, opt, intensity, {}, {}};
            for (int i = 0; i <= W; ++i) {
                const std::size_t at = static_cast<std::size_t>(j) * cw + static_cast<std::size_t>(i);
                ++tr.rays.eye_rays;
                Hit first;
                corners[at] = tr.trace(cam.eye_ray(i, j), 1.0f, &first);
                if (opt.id_buffer) res.id_buffer[at] = first.hit ? first.entity : -1;
                if (opt.t_buffer) res.t_buffer[at] = first.hit ? first.t : -1.0f;
            }
            row_rays[static_cast<std::size_t>(j)] = tr.rays;
            row_trav[static_cast<std::size_t>(j)] = tr.trav;
            rows_done.fetch_add(1);
        }
    };
    auto t0 = std::chrono::steady_clock::now();
    if (opt.progress) {
        // All rows go to the pool; the calling thread only reports progress, then joins.
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
        while (rows_done.load() < static_cast<int>(ch)) {
            opt.progress(rows_done.load(), static_cast<int>(ch));
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        for (std::thread& t : pool) t.join();
    } else {
        std::vector<std::thread> pool;
        for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
        worker();
        for (std::thread& t : pool) t.join();
    }
    if (opt.progress) opt.progress(static_cast<int>(ch), static_cast<int>(ch));
    res.stats.trace_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    res.stats.setup_seconds = prep.setup_seconds;
    res.stats.threads = threads;
    res.stats.epsilon = opt.epsilon;
    for (std::size_t j = 0; j < ch; ++j) {
        res.stats.rays += row_rays[j];
        for (std::size_t k = 0; k < kRayKinds; ++k) res.stats.traversal[k] += row_trav[j][k];
    }
    res.image.width = W;
    res.image.height = H;
    res.image.rgb.resize(static_cast<std::size_t>(W) * static_cast<std::size_t>(H) * 3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t a = static_cast<std::size_t>(y) * cw + static_cast<std::size_t>(x);
            Col c = corners[a];
            c += corners[a + 1];
            c += corners[a + cw];
            c += corners[a + cw + 1];
            std::uint8_t* px = &res.image.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(x)) * 3];
            px[0] = to_byte(c.r * 0.25f);
            px[1] = to_byte(c.g * 0.25f);
            px[2] = to_byte(c.b * 0.25f);
        }
    return res;
}

} // namespace nesshi::rt
