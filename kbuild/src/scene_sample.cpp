// A scene's IC work, sampled natively (scene_sample.hpp), and a kernel's cycles on it.
#include "kbuild/scene_sample.hpp"

#include "kbuild/runner.hpp"

#include "kbuild/ray_tag.hpp"

#include "iss/stats.hpp"
#include "kernels/abi.hpp"
#include "kernels/image.hpp"
#include "rt/camera.hpp"
#include "rt/shading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace nesshi::kbuild {

namespace abi = kernels::abi;

namespace {

// The native renderer's ray tree (rt/render.cpp), recording each non-empty voxel visit.
struct Sampler {
    const rt::PreparedScene& prep;
    const rt::RenderOptions& opt;
    float intensity;
    std::map<int, std::uint32_t> voxel_index; // grid address -> index into lists
    std::vector<int> voxels;                  // grid address of each list
    std::vector<abi::Visit> visits;
    rt::RayStats rays;
    rt::TraceCounters counters;

    void visit(const rt::Ray& ray, const rt::VoxelSpan& span) {
        const auto [at, fresh] = voxel_index.emplace(span.addr, static_cast<std::uint32_t>(voxels.size()));
        if (fresh) voxels.push_back(span.addr);
        abi::Visit v;
        v.tag = abi::Tag{static_cast<std::uint32_t>(visits.size()) & 0xffffu, tag_kind(ray.kind),
                         static_cast<std::uint32_t>(ray.depth)}.word() |
                abi::kTagReturn;
        v.voxel = at->second;
        v.t_in = span.t_in;
        v.t_out = span.t_out;
        for (int k = 0; k < 3; ++k) v.o[k] = ray.o[k], v.d[k] = ray.d[k];
        v.tmin = ray.tmin;
        v.tmax = ray.tmax;
        visits.push_back(v);
    }

    rt::Hit nearest(const rt::Ray& ray) {
        rt::Hit best;
        rt::VoxelWalk walk(prep.grid, ray);
        rt::VoxelSpan span;
        while (walk.next(span, counters)) {
            visit(ray, span);
            if (rt::intersect_voxel_nearest(prep.grid, prep.shapes, ray, span, best, counters)) break;
        }
        return best;
    }

    void any(const rt::Ray& ray) {
        rt::VoxelWalk walk(prep.grid, ray);
        rt::VoxelSpan span;
        while (walk.next(span, counters)) {
            visit(ray, span);
            if (rt::intersect_voxel_any(prep.grid, prep.shapes, ray, span, counters)) return;
        }
    }

    void trace(const rt::Ray& ray, float weight) {
        const rt::Hit hit = nearest(ray);
        if (!hit.hit) return;
        const rt::ShadePlan plan = rt::plan_shade(prep, opt, intensity, ray, hit, weight, rays);
        for (const rt::LightTerm& l : plan.lights) any(l.shadow);
        if (plan.reflect) trace(plan.reflect_ray, plan.reflect_weight);
        if (plan.refract) trace(plan.refract_ray, plan.refract_weight);
    }
};

// `n` + 1 evenly spread values of 0..size (all of them when size <= n).
std::vector<int> raster_of(int size, int n) {
    std::vector<int> out;
    const int steps = std::min(size, n);
    for (int k = 0; k <= steps; ++k) out.push_back(static_cast<int>(static_cast<long long>(k) * size / steps));
    return out;
}

} // namespace

std::string SceneSample::what() const {
    return fmt::format("{} visits by the rays of {} pixel corners", visits.size(), corners);
}

const SceneSample& LazySceneSample::get() const {
    if (!sample_) sample_ = sample_scene(*prep_, *opt_);
    return *sample_;
}

SceneSample sample_scene(const rt::PreparedScene& prep, const rt::RenderOptions& opt, int raster) {
    const int W = std::max(1, opt.width), H = std::max(1, opt.height);
    const rt::Camera cam(prep.scene.view, W, H);
    Sampler s{prep, opt, rt::light_intensity(prep.scene.lights.size()), {}, {}, {}, {}, {}};
    SceneSample out;
    for (int j : raster_of(H, raster - 1))
        for (int i : raster_of(W, raster - 1)) {
            s.trace(cam.eye_ray(i, j), 1.0f);
            ++out.corners;
        }
    // Only the shapes the visited lists name, renumbered in scene order (ties keep their order).
    std::vector<std::uint32_t> renumber(prep.shapes.shapes.size(), 0);
    std::vector<char> used(prep.shapes.shapes.size(), 0);
    const rt::Grid& g = prep.grid;
    for (int addr : s.voxels)
        for (std::uint32_t k = g.offsets[static_cast<std::size_t>(addr)]; k < g.offsets[static_cast<std::size_t>(addr) + 1]; ++k)
            used[g.prims[k]] = 1;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i]) {
            renumber[i] = static_cast<std::uint32_t>(out.shapes.size());
            out.shapes.push_back(prep.shapes.shapes[i]);
        }
    for (int addr : s.voxels) {
        std::vector<std::uint32_t>& l = out.lists.emplace_back();
        for (std::uint32_t k = g.offsets[static_cast<std::size_t>(addr)]; k < g.offsets[static_cast<std::size_t>(addr) + 1]; ++k)
            l.push_back(renumber[g.prims[k]]);
    }
    out.visits = std::move(s.visits);
    return out;
}

std::uint64_t sample_busy_cycles(const std::shared_ptr<const iss::Program>& prog, const SceneSample& s) {
    KernelRunner run(prog);
    const kernels::IcImage im = kernels::ic_image_lists(s.lists, s.shapes, true, list_layout(*prog));
    run.load(im.resident);
    run.load(im.global);
    run.run();
    for (const abi::Visit& v : s.visits) {
        run.feed(v.words());
        run.run();
        run.out1.drain_all();
        run.out2.drain_all();
    }
    const iss::Stats st = iss::compute_stats(*run.proc, 0);
    return st.processing_cycles + st.communication_cycles;
}

} // namespace nesshi::kbuild
