// An outside program built against an installed Nesshisen (find_package or pkg-config): assembles
// a bundle for the os preset, runs it on the simulator and reads the statistics, bundles a
// straight-line block with the scheduler, and builds the OS kernel, which runs its compiled runs
// when the build made them (EXPECT_COMPILED: they register themselves when the program starts).
#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/processor.hpp"
#include "iss/stats.hpp"
#include "kbuild/runner.hpp"
#include "kernels/sources.hpp"
#include "sched/block.hpp"

#include <cstdio>

int main() {
    using namespace nesshi;
    const isa::Machine m = isa::load_machine("os");
    const auto r = assembler::assemble_string("li r1, 6\nli r2, 7\nmul r3, r1, r2\nhalt\n", "six_by_seven.s", m, {});
    if (!r.ok) {
        std::fprintf(stderr, "%s", r.diagnostics.c_str());
        return 1;
    }
    iss::Processor p(iss::load_program(r.object, m));
    if (p.run(1000) != iss::Status::Halted) return 1;
    const iss::Stats s = iss::compute_stats(p);
    std::printf("r3 = %u after %llu cycles, %llu ops\n", p.reg(3), static_cast<unsigned long long>(s.cycles),
                static_cast<unsigned long long>(s.ops));
    // The scheduler too (it links z3 and Gecode): two independent ops packed into one bundle.
    const sched::PackResult packed = sched::pack_source("#pack begin\n        li r1, 6\n        li r2, 7\n#pack end\n        halt\n", "t.pk", m);
    if (packed.blocks.size() != 1 || packed.blocks[0].bundles != 1) return 1;
    const kbuild::KernelRunner dda(kbuild::assemble_kernel(kernels::embedded(), "os/dda.s", "os"));
    if (dda.proc->compiled_runs() != bool(EXPECT_COMPILED)) {
        std::fprintf(stderr, "os/dda.s on os: compiled runs %s\n", dda.proc->compiled_runs() ? "on" : "off");
        return 1;
    }
    return p.reg(3) == 42 ? 0 : 1;
}
