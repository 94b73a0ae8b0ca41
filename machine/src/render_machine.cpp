// render: builds the machine's memory images and programs once, simulates each PE on a
// host thread, and gathers image, buffers and statistics.
#include "pe.hpp"

#include "base/write_file.hpp"
#include "kernels/abi.hpp"
#include "kernels/image.hpp"
#include "kbuild/runner.hpp"
#include "kbuild/scene_sample.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace nesshi::machine {

namespace abi = kernels::abi;
using namespace machine;

namespace {

MachineSetup build_setup(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo) {
    const kernels::SourceSet src = mo.kernels_dir.empty() ? kernels::embedded() : kernels::from_directory(mo.kernels_dir);
    const bool vliw = mo.model == Model::V;
    MachineSetup s;
    const isa::Machine& seq = mo.seq_machine.machine();
    s.os_prog = kbuild::assemble_kernel(src, kernels::kernel_path(vliw, false), vliw ? mo.os_machine.machine() : seq,
                                &s.os_build);
    // The IC kernel's candidates (on a preset: its committed kernel and the alternatives) are
    // measured on this scene.
    const kbuild::LazySceneSample sample(prep, opt);
    s.ic_prog = kbuild::assemble_kernel(src, kernels::kernel_path(vliw, true), vliw ? mo.ic_machine.machine() : seq,
                                &s.ic_build, vliw ? &sample : nullptr);
    const rt::Grid& g = prep.grid;
    if (!abi::os_sram_fits(g.geom.n[0], g.geom.n[1], g.geom.n[2]))
        throw std::runtime_error(fmt::format(
            "grid {}x{}x{} does not fit the OS SRAM: its padded occupancy map takes {} bytes from 0x{:x}, the SRAM "
            "ends at 0x{:x} (use a coarser grid)",
            g.geom.n[0], g.geom.n[1], g.geom.n[2], abi::os_padded_map_bytes(g.geom.n[0], g.geom.n[1], g.geom.n[2]),
            abi::kOsOcc, abi::kOsOccLimit));
    s.os_image = kernels::os_image(g.geom, g.occupancy);
    kernels::IcImage ic = kernels::ic_image(g.geom, g.offsets, g.prims, prep.shapes.shapes, mo.resident, kbuild::list_layout(*s.ic_prog));
    // The global memory's size is the IC machine's: its [[memory]] region at IC_GLOBAL.
    const isa::Machine& icm = s.ic_prog->machine();
    const isa::MemoryDesc* global = icm.memory_at(abi::kIcGlobal, 4);
    if (!global || global->base != abi::kIcGlobal)
        throw std::runtime_error(fmt::format("machine {} has no global memory at 0x{:x}", icm.name, abi::kIcGlobal));
    if (ic.global.bytes.size() > global->size)
        throw std::runtime_error(fmt::format("the IC data ({} bytes) do not fit the {} MiB global memory",
                                             ic.global.bytes.size(), global->size >> 20));
    s.ic_resident = std::move(ic.resident);
    s.global = std::make_shared<iss::PagedMemory>(global->size);
    if (!ic.global.bytes.empty()) s.global->write_bytes(ic.global.base - abi::kIcGlobal, ic.global.bytes);
    s.sc_prices = OpPrices{seq.latency};
    return s;
}

// Model S's time as the sum of an M run's stage loads is exact when the work does not depend on
// timing: no cache (its misses follow the access order), unbounded FIFOs (no blocked sends), and
// interleaved DIS (dynamic balancing hands corners out by timing).
bool s_time_is_exact(const Options& mo) {
    return !mo.cache.enabled && mo.fifo_capacity == 0 && !mo.dynamic_balance;
}

} // namespace

static_assert(abi::get("MSG_VISIT") >= abi::get("MSG_NEW") && abi::get("MSG_VISIT") >= abi::get("MSG_HIT")); // the longest

int deadlock_free_ray_slots(std::size_t fifo_capacity) {
    if (fifo_capacity == 0) return 0;
    return static_cast<int>(std::clamp<std::size_t>(fifo_capacity / kLongestMessageWords, 1, abi::kOsSlots));
}

Result render(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo) {
    if (mo.pes < 1) throw std::invalid_argument("the machine needs at least one PE");
    if (mo.fifo_capacity != 0 && mo.fifo_capacity < 16)
        throw std::invalid_argument("FIFO capacity must be 0 (unbounded) or at least 16 words (a VISIT is 12)");
    if (mo.window < 1) throw std::invalid_argument("the DIS window must be at least 1 corner");
    if (mo.ray_slots < 0 || mo.ray_slots > static_cast<int>(abi::kOsSlots))
        throw std::invalid_argument(fmt::format("ray slots must be 1 to {} (0: all)", abi::kOsSlots));
    // The host's clock starts once the kernels are built (scheduled for a new machine: seconds),
    // so that it times the simulation; their build has a figure of its own.
    const auto t_setup = std::chrono::steady_clock::now();
    const MachineSetup setup = build_setup(prep, opt, mo);
    const auto t0 = std::chrono::steady_clock::now();

    const int W = opt.width, H = opt.height;
    const std::size_t ncorners = (static_cast<std::size_t>(W) + 1) * (static_cast<std::size_t>(H) + 1);
    Result res;
    std::vector<rt::Col> colors(ncorners);
    if (opt.id_buffer) res.render.id_buffer.assign(ncorners, -1);
    if (opt.t_buffer) res.render.t_buffer.assign(ncorners, -1.0f);
    CornerSink sink{&colors, opt.id_buffer ? &res.render.id_buffer : nullptr,
                    opt.t_buffer ? &res.render.t_buffer : nullptr, W, H};

    int threads = 1;
    std::vector<PeResult> results = mo.dynamic_balance ? run_dynamic(setup, prep, opt, mo, ncorners, sink, threads)
                                                       : run_interleaved(setup, prep, opt, mo, ncorners, sink, threads);

    Stats& ms = res.machine;
    ms.os_kernel = setup.os_build;
    ms.ic_kernel = setup.ic_build;
    ms.model = mo.model;
    ms.threads = threads;
    for (const PeResult& r : results) {
        ms.total_cycles = std::max(ms.total_cycles, r.end);
        ms.pe_cycles.push_back(r.end);
        ms.per_pe.push_back({r.end, r.os, r.ic, r.sc, r.os_detail, r.ic_detail});
        iss::accumulate(ms.os_detail, r.os_detail);
        iss::accumulate(ms.ic_detail, r.ic_detail);
        ms.os += r.os;
        ms.ic += r.ic;
        ms.sc += r.sc;
        if (mo.model == Model::M && s_time_is_exact(mo)) ms.s_cycles = std::max(ms.s_cycles, r.os.load() + r.ic.load() + r.sc.load());
        ms.visits += r.visits;
        ms.returns += r.returns;
        ms.misses += r.misses;
        ms.hits += r.hits;
        ms.cache_accesses += r.cache_accesses;
        ms.cache_misses += r.cache_misses;
        ms.max_fifo_words = std::max(ms.max_fifo_words, r.max_fifo);
        ms.simulated_bundles += r.bundles;
        res.render.stats.rays += r.rays;
        for (std::size_t k = 0; k < rt::kRayKinds; ++k) res.render.stats.traversal[k] += r.traversal[k];
    }
    if (results.size() == 1) { // one PE: its hottest bundles too (a sum over PEs has none)
        ms.os_detail = results[0].os_detail;
        ms.ic_detail = results[0].ic_detail;
    }
    ms.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ms.machine_setup_seconds = std::chrono::duration<double>(t0 - t_setup).count();
    res.render.image = rt::resolve_image(colors, W, H);
    res.render.stats.setup_seconds = prep.setup_seconds;
    res.render.stats.trace_seconds = ms.wall_seconds;
    res.render.stats.threads = threads;
    res.render.stats.epsilon = opt.epsilon;
    if (!mo.trace_json.empty()) write_trace_json(mo.trace_json, results);
    if (!mo.timeline_svg.empty()) base::write_file(mo.timeline_svg, timeline_svg(results));
    return res;
}

} // namespace nesshi::machine
