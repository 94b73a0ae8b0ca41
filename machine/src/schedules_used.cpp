// The lines a run prints before it starts when a stage runs on another description than its
// preset: which kernel file was scheduled for it, and what that schedule costs per step and per
// primitive (the headline rows of `nesshi kernels` on the same machines).
#include "machine/kernel_report.hpp"
#include "kbuild/runner.hpp"

#include "isa/machine.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace nesshi::machine {

namespace {

struct Stage {
    const char* role;   // "os", "ic", "seq"
    bool intersect;     // which of the role's kernels
    std::vector<std::string> metrics; // the rows shown
};

std::string row(const KernelReport& r, const std::string& metric, const std::string& role) {
    const KernelRow* k = r.find(metric, role);
    if (!k) return {};
    std::string s = fmt::format("{} {:.2f}", metric, k->cycles);
    if (metric == "dda_step" && k->res_mii > 0) // the loop: how far from its bounds
        s += fmt::format(" (ResMII {:.2f}, RecMII {:.2f})", k->res_mii, k->rec_mii);
    return s;
}

} // namespace

std::string schedules_used(const Options& mo, const std::vector<Model>& models) {
    const kernels::SourceSet src = mo.kernels_dir.empty() ? kernels::embedded() : kernels::from_directory(mo.kernels_dir);
    const KernelMachines km{mo.os_machine, mo.ic_machine, mo.seq_machine};
    std::vector<Stage> stages;
    auto runs = [&](Model m) { return std::find(models.begin(), models.end(), m) != models.end(); };
    if (runs(Model::V)) {
        if (!km.os.same_as_preset("os")) stages.push_back({"os", false, {"dda_step", "dda_init"}});
        if (!km.ic.same_as_preset("ic")) stages.push_back({"ic", true, {"triangle", "quadric_hit", "quadric2_hit", "cylinder_hit"}});
    }
    if ((runs(Model::S) || runs(Model::M)) && !km.seq.same_as_preset("seq")) {
        stages.push_back({"seq", false, {"dda_step", "dda_init"}});
        stages.push_back({"seq", true, {"triangle", "quadric_hit"}});
    }
    if (stages.empty()) return {};
    const KernelReport report = kernel_report(src, km);
    std::string out = "schedules, in cycles (`nesshi kernels` with the same --*-machine options has the whole table):\n";
    for (const Stage& s : stages) {
        kbuild::KernelBuild b;
        (void)kbuild::assemble_kernel(src, kernels::kernel_path(s.role != std::string("seq"), s.intersect),
                              km.of(s.role).machine(), &b); // cached: the run builds it again for free
        std::vector<std::string> rows;
        for (const std::string& m : s.metrics)
            if (std::string r = row(report, m, s.role); !r.empty()) rows.push_back(std::move(r));
        std::string how = b.scheduled ? fmt::format(", {} blocks scheduled", b.blocks) : std::string(", as written");
        if (b.nops) how += fmt::format(", {} nops inserted", b.nops);
        out += fmt::format("  {} on {}: {}{}: {}\n", s.role, b.machine, b.source, how, fmt::join(rows, ", "));
        if (s.intersect && s.role != std::string("seq") && b.candidates > 1)
            out += fmt::format("    (of {} candidates, the fastest on the kernel workloads; a render takes the fastest on a sample "
                               "of its scene, and says which)\n",
                               b.candidates);
    }
    return out;
}

} // namespace nesshi::machine
