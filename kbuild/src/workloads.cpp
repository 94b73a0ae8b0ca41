// The kernel report's synthetic workloads (workloads.hpp): fixed seeds, so every run of the
// report measures the same rays on the same grids and shapes.
#include "kbuild/workloads.hpp"

#include "kbuild/synthetic_inputs.hpp"

#include "base/vec.hpp"
#include "kernels/abi.hpp"
#include "kernels/image.hpp"
#include "kernels/messages.hpp"
#include "kernels/shape_record.hpp"
#include "kernels/twins/dda.hpp"
#include "rt/shapes.hpp"

#include "iss/stats.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace nesshi::kbuild {

namespace {

constexpr int kGridRays = 300;
constexpr int kPrimitiveRays = 200;
constexpr int kPrimitives = 40;
constexpr int kShortLists = 64;
constexpr int kShortListRays = 2000;

// Random rays through the grid; each VISIT is answered with a RETURN (no hit).
void drive_dda(KernelRunner& run, std::mt19937& rng, int rays) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < rays; ++i) {
        base::Vec3f o{u(rng) * 30.0f, u(rng) * 30.0f, u(rng) * 30.0f};
        base::Vec3f tgt{u(rng) * 8.0f, u(rng) * 8.0f, u(rng) * 8.0f};
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::NewRay nr{kernels::abi::Tag{static_cast<std::uint32_t>(i) % kernels::abi::kOsSlots, kernels::abi::Kind::eye, 1}.word(),
                                {o.x, o.y, o.z}, {d.x, d.y, d.z}, 0.0f, std::numeric_limits<float>::infinity()};
        run.feed(nr.words());
        for (;;) {
            run.run();
            auto w = run.out1.drain_all();
            run.out2.drain_all();
            if (w.empty()) break;
            run.feed(std::array<std::uint32_t, 1>{w[0]});
        }
    }
}

WorkloadRun grid_run(const std::shared_ptr<const iss::Program>& prog, int n, double density, std::mt19937& rng) {
    WorkloadRun w{std::make_unique<KernelRunner>(prog), kGridRays, 0, {}};
    const OccupancyGrid g = random_grid(n, density, rng);
    w.run->load(kernels::os_image(g.g, g.occ));
    w.run->run();
    drive_dda(*w.run, rng, kGridRays);
    return w;
}

kernels::Shape shape_of(Workload w, std::mt19937& rng) {
    switch (w) {
    case Workload::Triangles: return random_triangle(rng, false);
    case Workload::TwoSidedSpheres: return random_sphere(rng, true);
    case Workload::Cylinders: return random_cylinder(rng);
    default: return random_sphere(rng, false);
    }
}

} // namespace

OccupancyGrid random_grid(int n, double density, std::mt19937& rng) {
    OccupancyGrid t;
    t.g = kernels::twins::cubic_grid(n, -10.0f, 20.0f);
    std::bernoulli_distribution full(density);
    t.occ.resize(static_cast<std::size_t>(n * n * n));
    for (auto& v : t.occ) v = full(rng) ? 1 : 0;
    return t;
}

kernels::Shape random_triangle(std::mt19937& rng, bool two) {
    std::uniform_real_distribution<double> p(-3.0, 3.0);
    base::Vec3d v0{p(rng), p(rng), p(rng)}, v1{p(rng), p(rng), p(rng)}, v2{p(rng), p(rng), p(rng)};
    return rt::triangle_record(v0, v1, v2, two);
}

kernels::Shape random_sphere(std::mt19937& rng, bool two) {
    std::uniform_real_distribution<float> p(-2.0f, 2.0f);
    kernels::Shape s;
    s.kind_flags = kernels::kShapeQuadric | (two ? kernels::kShapeTwoSided : 0u);
    s.w[0] = p(rng) * 0.2f, s.w[1] = p(rng) * 0.2f, s.w[2] = p(rng) * 0.2f;
    s.w[3] = s.w[4] = s.w[5] = 1.0f;
    s.w[12] = -1.0f;
    return s;
}

kernels::Shape random_cylinder(std::mt19937& rng) {
    kernels::Shape s = random_sphere(rng, false);
    s.w[5] = 0.0f;  // C: no z term
    s.w[2] = -2.0f; // from z = -2
    s.w[15] = 1.0f; // axis z
    s.w[16] = 4.0f; // length
    return s;
}

bool is_grid(Workload w) { return w == Workload::EmptyGrid || w == Workload::SparseGrid; }

DdaRuns run_dda(const std::shared_ptr<const iss::Program>& prog) {
    std::mt19937 rng(5);
    DdaRuns r;
    r.empty = grid_run(prog, 40, 0.0, rng);
    r.sparse = grid_run(prog, 20, 0.03, rng);
    return r;
}

DdaRuns run_dda(const kernels::SourceSet& sources, const std::string& role, const isa::Machine& machine) {
    KernelBuild build;
    DdaRuns r = run_dda(assemble_kernel(sources, kernels::kernel_path(role != "seq", false), machine, &build));
    r.empty.build = r.sparse.build = build;
    return r;
}

WorkloadRun run_intersect(const kernels::SourceSet& sources, const std::string& role, const isa::Machine& machine, Workload w) {
    KernelBuild build;
    WorkloadRun r = run_intersect(assemble_kernel(sources, kernels::kernel_path(role != "seq", true), machine, &build), w);
    r.build = std::move(build);
    return r;
}

std::uint64_t workload_busy_cycles(const std::shared_ptr<const iss::Program>& prog, const std::string& path) {
    auto busy = [](const WorkloadRun& w) {
        const iss::Stats st = iss::compute_stats(*w.run->proc, 0);
        return st.processing_cycles + st.communication_cycles;
    };
    if (path.find("dda") != std::string::npos) {
        const DdaRuns d = run_dda(prog);
        return busy(d.empty) + busy(d.sparse);
    }
    std::uint64_t sum = 0;
    for (Workload w : {Workload::Triangles, Workload::Spheres, Workload::SpheresMissed, Workload::TwoSidedSpheres, Workload::Cylinders,
                       Workload::ShortLists})
        sum += busy(run_intersect(prog, w));
    return sum;
}

// One voxel whose list holds the 40 shapes (ShortLists: 64 voxels of 1-12 of them); rays from z = 20
// aimed at the origin (or past it).
WorkloadRun run_intersect(const std::shared_ptr<const iss::Program>& prog, Workload w) {
    std::mt19937 rng(7);
    std::vector<kernels::Shape> shapes;
    std::vector<std::vector<std::uint32_t>> lists(1);
    const bool short_lists = w == Workload::ShortLists;
    const int rays = short_lists ? kShortListRays : kPrimitiveRays;
    double tests = 0;
    if (short_lists) { // kinds mixed; each list in index order, as the grid builds it
        constexpr Workload kinds[] = {Workload::Triangles, Workload::Spheres, Workload::TwoSidedSpheres, Workload::Cylinders};
        for (int i = 0; i < kPrimitives; ++i) shapes.push_back(shape_of(kinds[rng() % 4], rng));
        lists.assign(kShortLists, {});
        for (auto& l : lists) {
            std::vector<std::uint32_t> all(kPrimitives);
            for (int i = 0; i < kPrimitives; ++i) all[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(i);
            std::shuffle(all.begin(), all.end(), rng);
            l.assign(all.begin(), all.begin() + 1 + static_cast<int>(rng() % 12));
            std::sort(l.begin(), l.end());
        }
        for (int i = 0; i < rays; ++i) tests += static_cast<double>(lists[static_cast<std::size_t>(i % kShortLists)].size());
    } else {
        for (int i = 0; i < kPrimitives; ++i) shapes.push_back(shape_of(w, rng));
        for (int i = 0; i < kPrimitives; ++i) lists[0].push_back(static_cast<std::uint32_t>(i));
        tests = double{kPrimitiveRays} * kPrimitives;
    }
    WorkloadRun out{std::make_unique<KernelRunner>(prog), static_cast<double>(rays), tests, {}};
    KernelRunner& run = *out.run;
    const kernels::IcImage im = kernels::ic_image_lists(lists, shapes, true, list_layout(*prog));
    run.load(im.resident);
    run.load(im.global);
    run.run();
    const bool miss = w == Workload::SpheresMissed;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < rays; ++i) {
        base::Vec3f o{u(rng) * 20.0f, u(rng) * 20.0f, 20.0f};
        base::Vec3f tgt = miss ? base::Vec3f{30.0f, 30.0f, 0.0f} : base::Vec3f{u(rng) * 0.3f, u(rng) * 0.3f, 0.0f};
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::Visit v;
        v.tag = kernels::abi::Tag{static_cast<std::uint32_t>(i), kernels::abi::Kind::eye, 1}.word() | kernels::abi::kTagReturn;
        v.voxel = short_lists ? static_cast<std::uint32_t>(i % kShortLists) : 0;
        v.t_out = 1e30f;
        for (int k = 0; k < 3; ++k) v.o[k] = o[k], v.d[k] = d[k];
        v.tmax = std::numeric_limits<float>::infinity();
        run.feed(v.words());
        run.run();
        run.out1.drain_all();
        run.out2.drain_all();
    }
    return out;
}

} // namespace nesshi::kbuild
