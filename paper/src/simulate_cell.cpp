// The real cell runner: one scene x grid x model through the machine simulator. The only file of
// the paper module that calls machine::render, so everything else links and tests without it.
#include "paper/paper.hpp"

namespace nesshi::paper {

std::string simulate_cell(const CellKey& k, const CellProgressFn& progress) {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene(k.scene), k.grid);
    rt::RenderOptions ro; // SPD mode (no cut-off), depth 5: the project's reference conditions
    ro.width = ro.height = k.size;
    ro.threads = 1;
    machine::Options mo; // the paper's ideal conditions: 100% cache hits, unbounded FIFOs, no latency
    mo.model = k.model;
    mo.pes = 1;
    mo.threads = 1; // cells run concurrently instead: one host thread per cell
    mo.progress = progress;
    const machine::Result r = machine::render(prep, ro, mo);
    return machine::stats_json(prep, ro, mo, r);
}

} // namespace nesshi::paper
