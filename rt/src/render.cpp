// The native renderer: corner rows spread over threads, Whitted tracing with the SPD rules.
#include "rt/render.hpp"

#include "kernels/paper_figures.hpp"
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
            cost += kernels::kPaper.dda_step_vliw * static_cast<double>(c.voxel_steps) +
                    kernels::kPaper.triangle * static_cast<double>(c.triangle_tests) +
                    kernels::kPaper.quadric * static_cast<double>(c.quadric_tests);
        choice.costs.emplace_back(n, cost);
        if (choice.n == 0 || cost < best) {
            best = cost;
            choice.n = n;
        }
    }
    return choice;
}

namespace {

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
        if (!hit.hit) return to_col(prep.scene.background);
        if (ray.kind == RayKind::eye) ++rays.eye_rays_hit;
        else ++rays.secondary_rays_hit;
        const ShadePlan plan = plan_shade(prep, opt, intensity, ray, hit, weight, rays);
        std::vector<char> blocked(plan.lights.size(), 0);
        TraceCounters& sc = trav[static_cast<std::size_t>(RayKind::shadow)];
        for (std::size_t k = 0; k < plan.lights.size(); ++k) {
            const Ray& sr = plan.lights[k].shadow;
            blocked[k] = opt.brute_force ? any_hit_brute(prep.shapes, sr, sc) : any_hit(prep.grid, prep.shapes, sr, sc);
            rays.shadow_rays_blocked += blocked[k] ? 1 : 0;
        }
        const Col refl = plan.reflect ? trace(plan.reflect_ray, plan.reflect_weight, nullptr) : Col{};
        const Col refr = plan.refract ? trace(plan.refract_ray, plan.refract_weight, nullptr) : Col{};
        return finish_shade(plan, blocked, refl, refr);
    }
};

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
    res.image = resolve_image(corners, W, H);
    return res;
}

} // namespace nesshi::rt
