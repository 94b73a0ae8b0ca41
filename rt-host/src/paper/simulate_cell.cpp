// The real cell runner: one scene x grid x model through the machine simulator. The only file of
// the paper module that calls render_machine, so everything else links and tests without it.
#include "rt/paper.hpp"

namespace nesshi::rt::paper {

std::string simulate_cell(const CellKey& k, const CellProgressFn& progress) {
    const PreparedScene prep = prepare(load_scene(k.scene), k.grid);
    RenderOptions ro; // SPD mode (no cut-off), depth 5: the project's reference conditions
    ro.width = ro.height = k.size;
    ro.threads = 1;
    MachineOptions mo; // the paper's ideal conditions: 100% cache hits, unbounded FIFOs, no latency
    mo.model = k.model;
    mo.pes = 1;
    mo.threads = 1; // cells run concurrently instead: one host thread per cell
    mo.progress = progress;
    const MachineResult r = render_machine(prep, ro, mo);
    return machine_stats_json(prep, ro, mo, r);
}

} // namespace nesshi::rt::paper
