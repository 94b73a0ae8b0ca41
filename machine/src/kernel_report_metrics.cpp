// The kernel report as data: what each row measures (kernel, workload, label regions, what it is
// counted per, the paper's figure, where its bounds come from) and the goals.
#include "machine/kernel_report.hpp"

#include <fmt/format.h>

namespace nesshi::machine {

namespace {

using kbuild::Workload;

using L = std::vector<std::string>;

KernelMetric metric(std::string name, const std::string& m, Workload w, L labels, PerWhat per, std::optional<double> paper) {
    KernelMetric k;
    k.metric = std::move(name);
    k.machine = m;
    k.workload = w;
    k.labels = std::move(labels);
    k.per = per;
    k.paper = paper;
    return k;
}

std::string paper_range(const char* what, const double (&ilp)[2], const double (&util)[2]) {
    return fmt::format("paper {} ILP {:.2f}-{:.2f}, util {:.2f}-{:.2f}", what, ilp[0], ilp[1], util[0], util[1]);
}

// The 3DDDA rows of one machine: the loop and set-up on the empty grid, the rest on the sparse one.
void dda_metrics(std::vector<KernelMetric>& out, const std::string& m) {
    const bool os = m == "os";
    KernelMetric step = metric("dda_step", m, Workload::EmptyGrid, os ? L{"loop", "__sa_kernel"} : L{"loop", "step_x", "not_x", "step_y", "step_z"},
                               PerWhat::Loads, os ? kPaper.dda_step_vliw : kPaper.dda_step_seq);
    if (os) {
        // The bounds over the loop body (the label through its branch back): the hand loop `loop`
        // (the os preset), or the kernel `__sa_kernel` of the loop pipelined for another machine,
        // not its exit code. One pass is as many steps as it loads occupancy bytes: two in the
        // hand loop, the kernel's unroll in the pipelined one.
        step.iterations_are_loads = true;
        step.bounds = BoundsFrom::Loops;
    } else {
        // branchy: the bounds per step from the x path (decision + step), the common case
        step.bounds = BoundsFrom::Path;
        step.path = "loop";
        step.note = "branchy: 9 ops per step";
    }
    out.push_back(step);
    out.push_back(metric("dda_init", m, Workload::EmptyGrid, {"new_ray", "fast_setup", "slow_setup", "setup2"}, PerWhat::Entries,
                         kPaper.dda_init));
    KernelMetric recv = metric("recv_ray", m, Workload::SparseGrid, {"next_ray"}, PerWhat::Entries, kPaper.fifo_ray);
    recv.note = "tag word + dispatch; the 8 ray words are received inside dda_init";
    out.push_back(recv);
    out.push_back(metric("send_ray", m, Workload::SparseGrid, {"visit_a", "visit_b"}, PerWhat::Entries, kPaper.fifo_ray));
    out.push_back(metric("resume", m, Workload::SparseGrid, {"resume"}, PerWhat::Entries, std::nullopt));
    KernelMetric whole = metric("whole_kernel", m, Workload::SparseGrid, {}, PerWhat::Rays, std::nullopt);
    whole.note = "per ray, processing cycles only";
    if (os) whole.note += "; " + paper_range("OS", kPaper.os_ilp, kPaper.os_util);
    out.push_back(whole);
}

// The intersection rows of one machine. ic: one straight-line body per primitive (dispatch
// included) in A/B variants, two primitives a pass; seq: the shared dispatch (next_prim) plus the
// kind's code with its early exits, counted per entry of the kind's first label.
void intersect_metrics(std::vector<KernelMetric>& out, const std::string& m) {
    const bool ic = m == "ic";
    // per entry of the first label's region (ic: both variants; seq: the kind's own code)
    auto primitive = [&](const char* name, Workload w, const L& ic_labels, const L& seq_labels, std::optional<double> paper,
                         std::string note) {
        KernelMetric k = metric(name, m, w, ic ? ic_labels : seq_labels, PerWhat::EntriesOf, paper);
        k.count_labels = ic ? ic_labels : L{seq_labels[1]};
        k.iterations = 2;
        if (ic) k.bounds = BoundsFrom::Regions;
        if (ic) k.run = ic_labels[0].substr(0, ic_labels[0].size() - 2); // "tri1_A" -> "tri1"
        k.note = std::move(note);
        return k;
    };
    const double quadric = kPaper.quadric + kPaper.quadric_load;
    out.push_back(primitive("triangle", Workload::Triangles, {"tri1_A", "tri1_B"}, {"next_prim", "tri1", "tri_common"},
                         kPaper.triangle + kPaper.triangle_load,
                         ic ? fmt::format("one-sided; paper {:.0f} + {:.0f} shape load", kPaper.triangle, kPaper.triangle_load)
                            : "one-sided, rays at the triangles: mean with early exits"));
    KernelMetric whole = metric("whole_kernel", m, Workload::Triangles, {}, PerWhat::Rays, std::nullopt);
    whole.note = "per ray, 40 triangles; processing only";
    if (ic) whole.note += "; " + paper_range("IC", kPaper.ic_ilp, kPaper.ic_util);
    out.push_back(whole);
    // A hybrid kernel's long lists also pass its entry to the loops and end at the loops' own labels.
    KernelMetric recv = metric("recv_ray", m, Workload::Triangles, {"next_ray", "from_dispatch"}, PerWhat::EntriesOf, kPaper.fifo_ray);
    recv.count_labels = {"next_ray"};
    out.push_back(recv);
    out.push_back(metric("send_ray", m, Workload::Triangles, {"done", "hit", "return", "done_loops", "hit_loops", "return_loops"},
                         PerWhat::Entries, kPaper.fifo_ray));
    const std::string load = fmt::format("paper {:.0f} + {:.0f} load", kPaper.quadric, kPaper.quadric_load);
    out.push_back(primitive("quadric_hit", Workload::Spheres, {"ball1_A", "ball1_B"}, {"next_prim", "ball1", "quad_roots", "sph_root"},
                         quadric,
                         ic ? "one-sided plain sphere (CODE_BALL1); branch-free: hit = miss; " + load
                            : "one-sided plain sphere, two real roots; " + load));
    out.push_back(primitive("quadric_miss", Workload::SpheresMissed, {"ball1_A", "ball1_B"},
                         {"next_prim", "ball1", "quad_roots", "sph_root"}, std::nullopt, "sphere, discriminant < 0"));
    out.push_back(primitive("quadric2_hit", Workload::TwoSidedSpheres, {"sph2_A", "sph2_B"},
                         {"next_prim", "sph2", "quad_common", "quad_roots", "sph_root", "sph_two"}, quadric,
                         "two-sided sphere: both roots"));
    out.push_back(primitive("cylinder_hit", Workload::Cylinders, {"quad1_A", "quad1_B"}, {"next_prim", "quad1", "quad_common", "quad_roots"},
                         quadric, "one-sided quadric with axial clip (cylinder)"));
}

} // namespace

const std::vector<KernelMetric>& kernel_metrics() {
    static const std::vector<KernelMetric> metrics = [] {
        std::vector<KernelMetric> out;
        dda_metrics(out, "os");
        dda_metrics(out, "seq");
        intersect_metrics(out, "ic");
        intersect_metrics(out, "seq");
        return out;
    }();
    return metrics;
}

const std::vector<KernelGoal>& kernel_goals() {
    static const std::vector<KernelGoal> goals = {
        {"voxel step on os", "dda_step", {"os"}, false, 6},
        {"triangle on ic", "triangle", {"ic"}, false, 20},
        {"quadric on ic", "quadric_hit", {"ic"}, false, 25},
        {"ILP", "whole_kernel", {"os", "ic"}, true, 3.0},
    };
    return goals;
}

} // namespace nesshi::machine
