// The real cell runner: one scene x grid x model through the machine simulator. The only file of
// the paper module that calls machine::render, so everything else links and tests without it.
#include "paper/paper.hpp"

namespace nesshi::paper {

namespace {

rt::RenderOptions cell_render_options(const CellKey& k) {
    rt::RenderOptions ro; // SPD mode (no cut-off), depth 5: the project's reference conditions
    ro.width = ro.height = k.size;
    ro.threads = 1;
    return ro;
}

// The paper's ideal conditions (100% cache hits, unbounded FIFOs, no latency) on base's machines.
machine::Options cell_machine_options(const CellKey& k, const machine::Options& base) {
    machine::Options mo = base;
    mo.model = k.model;
    mo.pes = 1;
    mo.threads = 1; // cells run concurrently instead: one host thread per cell
    return mo;
}

} // namespace

std::string simulate_cell(const CellKey& k, const machine::Options& base, const CellProgressFn& progress) {
    const rt::PreparedScene prep = rt::prepare(rt::load_scene(k.scene), k.grid);
    const rt::RenderOptions ro = cell_render_options(k);
    machine::Options mo = cell_machine_options(k, base);
    mo.progress = progress;
    const machine::Result r = machine::render(prep, ro, mo);
    return rt::stats_text(machine::stats_json(prep, ro, mo, r));
}

machine::Provenance cell_provenance(const CellKey& k, const machine::Options& base) {
    return machine::provenance(k.scene, k.grid, cell_render_options(k), cell_machine_options(k, base));
}

} // namespace nesshi::paper
