// The simulated machine: a scene rendered through PEs whose OS and IC stages are ISS instances
// running the kernels of kernels/, with the SC stage in C++ under a counted cycle-cost model.
//
//   rt::PreparedScene prep = rt::prepare(rt::load_scene("balls:1"), 20);
//   machine::Options mo;  mo.model = machine::Model::V;
//   machine::Result r = machine::render(prep, render_options, mo);
//   r.render.image ... r.machine.total_cycles, r.machine.os.processing ...
//
// Models change timing, never results: S, M, V and render_native give identical images, ID
// buffers and ray counts. Deterministic: the same inputs give the same cycles for any thread
// count (each PE is simulated by one host thread from start to end; PEs share only read-only
// data). See machine/README.md for the scheduling and cost models.
#pragma once
#include "kbuild/kernel_build.hpp"
#include "kbuild/stage_machine.hpp"
#include "iss/cache.hpp"
#include "iss/stats.hpp"
#include "kernels/abi.hpp"
#include "rt/render.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace nesshi::machine {

enum class Model : std::uint8_t {
    S, // one seq processor runs OS, IC and SC in turn (one clock)
    M, // OS, IC, SC each on a seq processor, pipelined through FIFOs
    V, // VLIW OS (os) and IC (ic), SC on seq, pipelined through FIFOs
};
const char* model_name(Model m);
bool parse_model(const std::string& s, Model& out);

// The IC cache over global memory (iss::SetAssocCache) when enabled; else the paper's ideal 100% hits.
struct CacheOptions : iss::CacheGeometry {
    bool enabled = false;
};

struct Options {
    Model model = Model::V;
    int pes = 1;                      // processing elements
    // How DIS distributes the pixel corners over PEs. Interleaved: corner k to PE k mod pes, all
    // up front. Dynamic (the paper's load balancing): every `epoch` cycles DIS tops each PE up to
    // 2 x window corners, the PE with the most room first, so faster PEs take more.
    bool dynamic_balance = false;
    std::uint64_t epoch = 20000;
    int threads = 0;                  // host threads (0 = all cores); never changes the cycles
    int window = 64;                  // eye rays (pixel corners) in flight per PE (the DIS's limit)
    std::size_t fifo_capacity = 0;    // words per FIFO; 0 = unbounded (the paper's ideal)
    // Rays in flight per PE: the ray slots SC hands out (each ray it or DIS sends to the OS holds
    // one until its MISS or HIT comes back); 0 = all OS_SLOTS (4096). The window bounds corners,
    // not rays: every hit spawns shadow, reflection and refraction rays. A ray has one message in
    // the FIFOs at a time, at most 12 words (a VISIT), so with at most fifo_capacity / 12 rays in
    // flight no FIFO ever fills and bounded FIFOs cannot deadlock (deadlock_free_ray_slots).
    int ray_slots = 0;
    std::uint32_t fifo_latency = 0;   // extra cycles between a send and the receive (ideal: 0)
    // Host switching of a PE's stages: the cycles a stage may run past its turn before the host
    // switches (no result depends on it). 0: kQuantum, or kTracedQuantum in a traced run, whose
    // samples of FIFO words and activity are taken at each switch (so a longer run between
    // switches draws them coarser, and the stage that ran ahead adds its sends early).
    std::uint64_t quantum = 0;
    static constexpr std::uint64_t kQuantum = 256, kTracedQuantum = 32;
    CacheOptions cache;
    // IC data placement (kernels/image.hpp): the records, voxel table and lists go to the resident
    // memory when they all fit in it; else the most-referenced shape records (by the number of voxel
    // lists holding them) fill it and the other records, the table and the lists go to global
    // memory (behind the cache). false: everything in global memory.
    bool resident = true;
    bool checked = false;             // ISS checked engine (ports and hazards checked dynamically)
    std::string kernels_dir;          // a folder of kernel sources overriding the built-in ones ("" = built in)
    // The stages' machine descriptions, loaded where they are named (kbuild/stage_machine.hpp): model V
    // runs OS and IC on os_machine and ic_machine, models S and M both on seq_machine; the SC's
    // operation prices come from seq_machine. The kernels are assembled for them; a description
    // they cannot run on is an error that names the first problem.
    kbuild::StageMachine os_machine{"os"}, ic_machine{"ic"}, seq_machine{"seq"};
    std::string trace_json;           // Chrome/Perfetto trace of activity and FIFO occupancy ("" = none)
    std::string timeline_svg;         // the same as a picture: stage busy fractions and FIFO words over time ("" = none)
    bool traced() const { return !trace_json.empty() || !timeline_svg.empty(); } // activity and FIFO samples kept
    std::uint64_t effective_quantum() const { return quantum ? quantum : traced() ? kTracedQuantum : kQuantum; }
    std::uint64_t max_cycles = 0;     // per PE; 0 = no limit. Exceeding it is an error.
    // Called from the calling thread about 10 times a second with (corner rays done, total).
    std::function<void(std::uint64_t, std::uint64_t)> progress;
};

// One stage's cycles, summed over PEs. processing + communication + wait = elapsed for each
// processor (elapsed = that processor's clock when its PE finished).
struct StageCycles {
    std::uint64_t processing = 0, communication = 0, wait = 0;
    std::uint64_t bundles = 0, ops = 0;     // processing_ops over processing cycles gives ilp
    std::uint64_t processing_ops = 0;
    std::uint64_t units = 1;                // issue slots of the machine
    std::uint64_t words_received = 0, words_sent = 0;
    bool modelled = false;                  // SC: counted operations, not simulated
    double ilp() const { return processing ? static_cast<double>(processing_ops) / static_cast<double>(processing) : 0; }
    double utilization() const { return ilp() / static_cast<double>(units); }
    std::uint64_t load() const { return processing + communication; } // the paper's Table 2 "load"
    std::uint64_t elapsed() const { return processing + communication + wait; }
    StageCycles& operator+=(const StageCycles& o);
};

// One PE's stages. Each processor's clock runs to the PE's end: processing + communication +
// wait = end for each of os, ic and sc.
struct PeCycles {
    std::uint64_t end = 0;
    StageCycles os, ic, sc;
    iss::Stats os_detail, ic_detail; // what `nesshi sim` reports for the PE's OS and IC processors
};

struct Stats {
    Model model = Model::V;
    std::uint64_t total_cycles = 0;        // the slowest PE's finishing time
    // Model M runs also give model S's time: one processor executing the same instruction streams
    // takes the sum of the three stages' loads (processing + communication) per PE; the slowest
    // PE's. Equal to a separate model-S run (tested) when the work does not depend on timing (no
    // cache, unbounded FIFOs, interleaved DIS); 0 otherwise and for models S and V.
    std::uint64_t s_cycles = 0;
    StageCycles os, ic, sc;                // summed over PEs
    // The OS's and the IC's processor statistics (units, register ports with histograms, ILP
    // histogram, per-label regions) summed over PEs; with one PE also its hottest bundles.
    iss::Stats os_detail, ic_detail;
    std::vector<std::uint64_t> pe_cycles;  // finishing time of each PE
    std::vector<PeCycles> per_pe;          // each PE's own stage cycles (os, ic, sc are their sums)
    std::uint64_t visits = 0, returns = 0, misses = 0, hits = 0; // FIFO messages
    std::uint64_t cache_accesses = 0, cache_misses = 0;
    std::uint64_t max_fifo_words = 0;      // highest occupancy seen on any FIFO
    kbuild::KernelBuild os_kernel, ic_kernel;      // how the OS and IC stages' kernels were built
    double wall_seconds = 0;               // host time of the simulation
    double machine_setup_seconds = 0;      // host time before it: kernels built (or loaded), memories laid out
    std::uint64_t simulated_bundles = 0;   // bundles issued by every ISS instance
    int threads = 1;
    double bundles_per_second() const { return wall_seconds > 0 ? static_cast<double>(simulated_bundles) / wall_seconds : 0; }
};

struct Result {
    rt::RenderResult render; // image, buffers, ray counts (traversal counters: only `rays` is filled)
    Stats machine;
};

// Throws std::runtime_error on a deadlock (bounded FIFOs), a kernel fault, a memory-capacity
// error (grid too large for the OS SRAM, data too large for IC memory) or max_cycles exceeded.
Result render(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo);

// The most rays in flight with which FIFOs of `fifo_capacity` words never fill: capacity / 12 (the
// longest message, a VISIT), at least 1; 0 (no limit needed) for unbounded FIFOs.
inline constexpr std::size_t kLongestMessageWords = kernels::abi::get("MSG_VISIT");
int deadlock_free_ray_slots(std::size_t fifo_capacity);


// Stats JSON: render's stats_json plus "cycles", "machine" and "host" for the machine; "traversal"
// keeps only `rays` per kind (the machine counts no voxel steps or tests). See docs/stats-json.md.
nlohmann::json stats_json(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo, const Result& r);
// A stage's figures as the stats JSON holds them ("cycles.os", ...), and read back (a paper cell,
// a sweep): the one place that names their keys. The reader throws std::runtime_error naming
// `where` + the key ("cycles.os.wait") that is missing or not a count.
nlohmann::json stage_cycles_json(const StageCycles& c);
StageCycles stage_cycles_from_json(const nlohmann::json& stage, const std::string& where);
// The Table 2 row of this run and the per-stage summary, for the terminal.
std::string format_stats(const Stats& s);

} // namespace nesshi::machine
