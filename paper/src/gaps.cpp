// The gap attribution: the paper's Table 2 cycles against ours, priced at the paper's step costs.
#include "paper/gaps.hpp"
#include "paper/paper.hpp"
#include "paper/published.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

namespace {

using VK = SceneVariant::Kind;
constexpr SceneVariant kVariants[] = {
    {"tetra", VK::view_angle, 22.5},
    {"balls", VK::floor_scale, 0.5},
    {"tree", VK::floor_scale, 0.5},
};

// Only hypotheses that fit every grid of a scene, and agree with the paper's other columns, are
// adopted. Candidates that fit one column and contradict another (two roots, floor) are reported
// beside, not adopted: their part of the gap stays unexplained.
constexpr GapAdoption kAdopted[] = {
    {"tetra", "OS", "view 22.5", "the view that reproduces tetra's IC must also be OS's workload"},
    {"tetra", "IC", "view 22.5",
     "IC within 4% of the paper at grids 20, 50, 100; VISITs within 15% of its IC communication / 25"},
};

constexpr double kM = 1e6; // the published tables are in millions of cycles

const HypothesisResult* find_hypothesis(const std::vector<HypothesisResult>& hs, std::string_view name) {
    for (const HypothesisResult& h : hs)
        if (h.name == name) return &h;
    return nullptr;
}

std::optional<std::string> adopted(std::string_view scene, std::string_view stage) {
    for (const GapAdoption& a : kAdopted)
        if (a.scene == scene && a.stage == stage) return std::string(a.hypothesis);
    return std::nullopt;
}

} // namespace

std::span<const SceneVariant> scene_variants() { return kVariants; }

std::string SceneVariant::name() const {
    return kind == Kind::view_angle ? fmt::format("view {:g}", value) : fmt::format("floor x{:g}", value);
}

rt::Scene apply_variant(rt::Scene scene, const SceneVariant& v) {
    if (v.kind == SceneVariant::Kind::view_angle) {
        scene.view.angle = v.value;
        return scene;
    }
    rt::Entity* floor = nullptr;
    double widest = 0;
    for (rt::Entity& e : scene.entities) {
        if (e.kind != rt::Entity::Kind::polygon) continue;
        rt::Box b;
        for (const rt::Vec3d& p : e.verts) b.add(p);
        const double w = std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
        if (w > widest) {
            widest = w;
            floor = &e;
        }
    }
    if (!floor) throw PaperError(fmt::format("{}: no polygon to scale as the floor", scene.name));
    for (rt::Vec3d& p : floor->verts) {
        p.x *= v.value;
        p.y *= v.value;
    }
    return scene;
}
std::span<const GapAdoption> gap_adoptions() { return kAdopted; }

WorkCounts work_counts(const rt::RenderStats& s) {
    WorkCounts w;
    w.eye_rays = static_cast<double>(s.rays.eye_rays);
    for (const rt::TraceCounters& c : s.traversal) {
        w.rays += static_cast<double>(c.rays);
        w.steps += static_cast<double>(c.voxel_steps);
        w.visits += static_cast<double>(c.nonempty_voxels);
        w.triangle_tests += static_cast<double>(c.triangle_tests);
        w.quadric_tests += static_cast<double>(c.quadric_tests);
        w.quadric_two_roots += static_cast<double>(c.quadric_two_roots);
    }
    return w;
}

Prices paper_prices() { return {}; }

double os_cycles(const WorkCounts& w, const Prices& p) { return p.init * w.eye_rays + p.step * w.steps; }

double ic_cycles(const WorkCounts& w, const Prices& p) {
    return p.triangle * w.triangle_tests + p.quadric * w.quadric_two_roots +
           p.quadric_miss * (w.quadric_tests - w.quadric_two_roots);
}

HypothesisResult two_roots_hypothesis(const WorkCounts& w) {
    Prices p = paper_prices();
    p.quadric_miss = kernels::kPaper.quadric_load; // the shape load alone
    return {"two roots", os_cycles(w, p), ic_cycles(w, p), w};
}

HypothesisResult init_every_ray_hypothesis(const WorkCounts& w) {
    const Prices p = paper_prices();
    return {"init every ray", p.init * w.rays + p.step * w.steps, ic_cycles(w, p), w};
}

GapRow attribute(std::string_view scene, int grid, const OursCell& ours, std::vector<HypothesisResult> hypotheses) {
    const PublishedStages* ps = find_published_stages(scene, grid);
    const PublishedComm* pc = find_published_comm(scene, grid);
    if (!ps || !pc) throw PaperError(fmt::format("the paper has no Table 2 row for {} at grid {}", scene, grid));
    const WorkCounts& w = ours.counts;
    if (!(ours.os > 0) || !(ours.ic > 0) || !(w.steps > 0) || !(w.triangle_tests + w.quadric_tests > 0))
        throw PaperError(fmt::format("{} grid {}: no cycles or no counts to compare", scene, grid));
    const Prices p = paper_prices();
    GapRow r;
    r.scene = std::string(scene);
    r.grid = grid;
    r.paper_os = ps->os * kM;
    r.paper_ic = ps->ic * kM;
    r.paper_os_comm = pc->os * kM;
    r.paper_ic_comm = pc->ic * kM;
    r.ours = ours;
    // The paper's eye rays are its 512 x 512 pixels (ours are the corners, 513 x 513).
    r.implied_steps = (r.paper_os - p.init * 512.0 * 512.0) / p.step;
    r.implied_visits = r.paper_ic_comm / kernels::kPaper.fifo_ray;
    const double tests = w.triangle_tests + w.quadric_tests;
    r.implied_tests = r.paper_ic / (ic_cycles(w, p) / tests);
    r.os_priced = os_cycles(w, p);
    r.ic_priced = ic_cycles(w, p);
    r.os_kernel = r.os_priced / ours.os;
    r.ic_kernel = r.ic_priced / ours.ic;
    r.hypotheses = std::move(hypotheses);
    r.os_adopted = adopted(scene, "OS");
    r.ic_adopted = adopted(scene, "IC");
    auto explained = [&](const std::optional<std::string>& name, double base, double HypothesisResult::*stage) {
        if (!name) return base;
        const HypothesisResult* h = find_hypothesis(r.hypotheses, *name);
        if (!h) throw PaperError(fmt::format("{} grid {}: hypothesis '{}' was not run", scene, grid, *name));
        return h->*stage;
    };
    r.os_explained = explained(r.os_adopted, r.os_priced, &HypothesisResult::os);
    r.ic_explained = explained(r.ic_adopted, r.ic_priced, &HypothesisResult::ic);
    return r;
}

LineFit fit_line(std::span<const double> x, std::span<const double> y) {
    if (x.size() != y.size() || x.size() < 2) throw PaperError("a line fit needs two points or more");
    const double n = static_cast<double>(x.size());
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        mx += x[i] / n;
        my += y[i] / n;
    }
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
    }
    if (!(sxx > 0)) throw PaperError("a line fit needs two different x");
    LineFit f;
    f.slope = sxy / sxx;
    f.intercept = my - f.slope * mx;
    return f;
}

} // namespace nesshi::paper
