// `nesshi kernels`: cycle report of the hand-scheduled kernels (kernels/), measured on the ISS.
//
// Each kernel is assembled from the source tree and run on synthetic inputs built with the ABI's
// image builders; figures come from the ISS's per-label region counters (a label's cycles over
// the number of times its first bundle issued). ResMII and RecMII are computed from the machine
// description and the measured region's operations: ResMII from unit classes (Hall bound over
// every subset of issue slots) and register-file ports; RecMII from the region as a loop body
// (longest latency path from a live-in read of a register to the region's last write of it).
#include "commands.hpp"

#include "machine/runner.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/channel.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"
#include "iss/stats.hpp"
#include "kernels/twins/dda.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <set>

namespace nesshi::cli {
namespace {

namespace fs = std::filesystem;
using kernels::abi::bits;

struct Row {
    std::string metric, machine;
    double cycles = 0;
    std::optional<double> paper;
    double ops = 0, ilp = 0, utilization = 0, res_mii = 0, rec_mii = 0;
    std::string note;
};

struct Run : machine::KernelRunner {
    Run(const kernels::SourceSet& dir, const std::string& rel, const std::string& machine)
        : KernelRunner(machine::assemble_kernel(dir, rel, machine)) {}
};

// Cycles and ops issued in the named regions, and how many times their first bundles issued.
struct Measure {
    double cycles = 0, ops = 0, entries = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges; // bundle ranges
};
Measure measure(const Run& run, const std::vector<std::string>& labels) {
    const iss::Stats st = iss::compute_stats(*run.proc, 0);
    Measure m;
    for (const auto& l : labels) {
        for (const auto& r : st.regions) {
            if (r.label != l) continue;
            m.cycles += static_cast<double>(r.cycles);
            m.ops += static_cast<double>(r.ops);
            m.entries += static_cast<double>(run.proc->counters().exec[r.first]);
            m.ranges.emplace_back(r.first, r.end);
        }
    }
    return m;
}

// ---- static bounds over a set of bundles -------------------------------------------------------

struct Op {
    isa::Instr in;
    std::uint32_t bundle;
};
std::vector<Op> ops_of(const iss::Program& p, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& ranges) {
    std::vector<Op> out;
    for (auto [a, b] : ranges)
        for (std::uint32_t pc = a; pc < b; ++pc)
            for (const isa::Instr& in : p.bundle_instrs(pc))
                if (in.info().kind != isa::Kind::Nop) out.push_back({in, pc});
    return out;
}

// Register reads and writes of one op as flat indices (0..127 IRF, 128..255 FPRF).
void regs_of(const isa::Instr& in, std::vector<int>& reads, int& write) {
    reads.clear();
    write = -1;
    for (const isa::RegOperand& r : isa::register_operands(in)) {
        const int flat = static_cast<int>(r.file) * 128 + r.reg;
        if (r.write) write = flat;
        else reads.push_back(flat);
    }
}

double res_mii(const isa::Machine& m, const std::vector<Op>& ops, double iterations) {
    double bound = 0;
    const std::size_t ns = m.slots.size();
    for (std::uint32_t mask = 1; mask < (1u << ns); ++mask) {
        double count = 0;
        for (const Op& o : ops) {
            bool inside = true;
            for (std::size_t s = 0; s < ns; ++s)
                if (m.slots[s].accepts(o.in.info().cls) && !(mask & (1u << s))) inside = false;
            if (inside) count += 1;
        }
        bound = std::max(bound, count / std::popcount(mask));
    }
    double reads[2] = {0, 0}, writes[2] = {0, 0};
    std::vector<int> r;
    int w;
    for (const Op& o : ops) {
        regs_of(o.in, r, w);
        for (int x : r) reads[x / 128] += 1;
        if (w >= 0) writes[w / 128] += 1;
    }
    for (int f = 0; f < 2; ++f) {
        const auto& rf = m.regs[static_cast<std::size_t>(f)];
        bound = std::max(bound, reads[f] / rf.read_ports);
        bound = std::max(bound, writes[f] / rf.write_ports);
    }
    return bound / iterations;
}

// The region as a loop body in bundle order: for each register read before it is written and
// written later, the longest latency path from that read to the last write (distance 1).
double rec_mii(const isa::Machine& m, const std::vector<Op>& ops, double iterations) {
    const std::size_t n = ops.size();
    std::vector<std::vector<int>> reads(n);
    std::vector<int> write(n);
    std::vector<int> lat(n);
    for (std::size_t i = 0; i < n; ++i) {
        regs_of(ops[i].in, reads[i], write[i]);
        lat[i] = static_cast<int>(m.latency_of(ops[i].in.info()));
    }
    double best = 0;
    std::set<int> written_before;
    std::map<int, std::size_t> last_writer;
    for (std::size_t i = 0; i < n; ++i)
        if (write[i] >= 0) last_writer[write[i]] = i;
    for (std::size_t s = 0; s < n; ++s) {
        for (int reg : reads[s]) {
            // live-in read: no earlier bundle writes reg
            bool live_in = true;
            for (std::size_t i = 0; i < n && ops[i].bundle < ops[s].bundle; ++i)
                if (write[i] == reg) live_in = false;
            if (!live_in || !last_writer.count(reg)) continue;
            // longest path from op s (value available at its issue) through RAW edges
            std::vector<double> dist(n, -1);
            dist[s] = 0;
            std::map<int, std::pair<double, std::size_t>> val; // reg -> (time value ready, producer)
            for (std::size_t i = s; i < n; ++i) {
                if (i != s) {
                    double d = -1;
                    for (int x : reads[i]) {
                        auto it = val.find(x);
                        if (it != val.end()) d = std::max(d, it->second.first);
                    }
                    dist[i] = d;
                }
                if (dist[i] >= 0 && write[i] >= 0) val[write[i]] = {dist[i] + lat[i], i};
                else if (write[i] >= 0) val.erase(write[i]);
            }
            auto it = val.find(reg);
            if (it != val.end() && it->second.second == last_writer[reg]) best = std::max(best, it->second.first);
        }
    }
    return best / iterations;
}

// The whole kernel's processing cycles, ops, ILP and utilisation per ray over `rays` rays.
Row whole_kernel_row(const std::string& machine, const Run& run, double rays, std::string note) {
    const iss::Stats st = iss::compute_stats(*run.proc, 0);
    Row t;
    t.metric = "whole_kernel";
    t.machine = machine;
    t.cycles = static_cast<double>(st.processing_cycles) / rays;
    t.ops = static_cast<double>(st.processing_ops) / rays;
    t.ilp = st.ilp;
    t.utilization = st.utilisation;
    t.note = std::move(note);
    return t;
}

Row make_row(const std::string& metric, const std::string& machine, const Run& run,
             const std::vector<std::string>& labels, double per, std::optional<double> paper, double iters_in_region,
             bool bounds) {
    const Measure ms = measure(run, labels);
    Row r;
    r.metric = metric;
    r.machine = machine;
    r.paper = paper;
    if (per <= 0) per = ms.entries;
    r.cycles = per > 0 ? ms.cycles / per : 0;
    r.ops = per > 0 ? ms.ops / per : 0;
    r.ilp = ms.cycles > 0 ? ms.ops / ms.cycles : 0;
    const isa::Machine& m = run.prog->machine();
    r.utilization = r.ilp / static_cast<double>(m.slots.size());
    if (bounds) {
        const auto ops = ops_of(*run.prog, ms.ranges);
        r.res_mii = res_mii(m, ops, iters_in_region);
        r.rec_mii = rec_mii(m, ops, iters_in_region);
    }
    return r;
}

// ---- workloads -----------------------------------------------------------------------------

struct Grid {
    kernels::twins::GridGeom g;
    std::vector<std::uint8_t> occ;
};
Grid make_grid(int n, double density, std::mt19937& rng) {
    Grid t;
    for (int k = 0; k < 3; ++k) {
        t.g.n[k] = n;
        t.g.lo[k] = -10.0f;
        t.g.cell[k] = 20.0f / static_cast<float>(n);
        t.g.hi[k] = t.g.lo[k] + static_cast<float>(n) * t.g.cell[k];
        t.g.inv_cell[k] = 1.0f / t.g.cell[k];
    }
    std::bernoulli_distribution full(density);
    t.occ.resize(static_cast<std::size_t>(n * n * n));
    for (auto& v : t.occ) v = full(rng) ? 1 : 0;
    return t;
}

// Random rays through the grid; each VISIT is answered with a RETURN (no hit).
void drive_dda(Run& run, std::mt19937& rng, int rays) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < rays; ++i) {
        base::Vec3f o{u(rng) * 30.0f, u(rng) * 30.0f, u(rng) * 30.0f};
        base::Vec3f tgt{u(rng) * 8.0f, u(rng) * 8.0f, u(rng) * 8.0f};
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::NewRay nr{kernels::abi::Tag{static_cast<std::uint32_t>(i % 4096), kernels::abi::Kind::eye, 1}.word(),
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

kernels::Shape tri_shape(std::mt19937& rng, bool two) {
    std::uniform_real_distribution<double> p(-3.0, 3.0);
    base::Vec3d v0{p(rng), p(rng), p(rng)}, v1{p(rng), p(rng), p(rng)}, v2{p(rng), p(rng), p(rng)};
    const base::Vec3d e1 = v1 - v0, e2 = v2 - v0, nn = base::cross(e1, e2);
    const double det = base::dot(nn, nn);
    const base::Vec3d rows[3] = {nn * (1.0 / det), base::cross(e2, nn) * (1.0 / det), base::cross(nn, e1) * (1.0 / det)};
    kernels::Shape s;
    s.kind_flags = kernels::kShapeTriangle | (two ? kernels::kShapeTwoSided : 0u);
    for (std::size_t i = 0; i < 3; ++i) {
        s.w[4 * i] = static_cast<float>(rows[i].x);
        s.w[4 * i + 1] = static_cast<float>(rows[i].y);
        s.w[4 * i + 2] = static_cast<float>(rows[i].z);
        s.w[4 * i + 3] = static_cast<float>(-base::dot(rows[i], v0));
    }
    return s;
}

kernels::Shape sphere_shape(std::mt19937& rng, bool two) {
    std::uniform_real_distribution<float> p(-2.0f, 2.0f);
    kernels::Shape s;
    s.kind_flags = kernels::kShapeQuadric | (two ? kernels::kShapeTwoSided : 0u);
    s.w[0] = p(rng) * 0.2f, s.w[1] = p(rng) * 0.2f, s.w[2] = p(rng) * 0.2f;
    s.w[3] = s.w[4] = s.w[5] = 1.0f;
    s.w[12] = -1.0f;
    return s;
}

// A cylinder of radius 1 along z through a point near the origin, length 4 (one-sided).
kernels::Shape cylinder_shape(std::mt19937& rng) {
    kernels::Shape s = sphere_shape(rng, false);
    s.w[5] = 0.0f;  // C: no z term
    s.w[2] = -2.0f; // from z = -2
    s.w[15] = 1.0f; // axis z
    s.w[16] = 4.0f; // length
    return s;
}

// One voxel whose list holds `count` shapes of one kind; rays aimed at the origin.
std::unique_ptr<Run> run_ic(const kernels::SourceSet& dir, const std::string& file, const std::string& machine, int kind, int count, int rays,
           bool miss) {
    std::mt19937 rng(7);
    std::vector<kernels::Shape> shapes;
    for (int i = 0; i < count; ++i)
        shapes.push_back(kind == 0   ? tri_shape(rng, false)
                         : kind == 1 ? sphere_shape(rng, false)
                         : kind == 2 ? sphere_shape(rng, true)
                                     : cylinder_shape(rng));
    std::vector<std::vector<std::uint32_t>> lists(1);
    for (int i = 0; i < count; ++i) lists[0].push_back(static_cast<std::uint32_t>(i));
    auto run = std::make_unique<Run>(dir, file, machine);
    const kernels::IcImage im = kernels::ic_image_lists(lists, shapes);
    run->load(im.resident);
    run->load(im.global);
    run->run();
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < rays; ++i) {
        base::Vec3f o{u(rng) * 20.0f, u(rng) * 20.0f, 20.0f};
        base::Vec3f tgt = miss ? base::Vec3f{30.0f, 30.0f, 0.0f} : base::Vec3f{u(rng) * 0.3f, u(rng) * 0.3f, 0.0f};
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::Visit v;
        v.tag = kernels::abi::Tag{static_cast<std::uint32_t>(i), kernels::abi::Kind::eye, 1}.word() | kernels::abi::kTagReturn;
        v.voxel = 0;
        v.t_out = 1e30f;
        for (int k = 0; k < 3; ++k) v.o[k] = o[k], v.d[k] = d[k];
        v.tmax = std::numeric_limits<float>::infinity();
        run->feed(v.words());
        run->run();
        run->out1.drain_all();
        run->out2.drain_all();
    }
    return run;
}

std::vector<Row> collect(const kernels::SourceSet& dir) {
    std::vector<Row> rows;
    for (const std::string machine : {"os", "seq"}) {
        const std::string file = machine + "/dda.s";
        std::mt19937 rng(5);
        // empty grid: every step is a loop step; the loop region counts its steps by its loads
        {
            Run run(dir, file, machine);
            Grid g = make_grid(40, 0.0, rng);
            run.load(kernels::os_image(g.g, g.occ));
            run.run();
            drive_dda(run, rng, 300);
            const bool os = machine == "os";
            const std::vector<std::string> loop = os ? std::vector<std::string>{"loop"}
                                                     : std::vector<std::string>{"loop", "step_x", "not_x", "step_y", "step_z"};
            // steps = executions of the bundles that load the occupancy byte
            double steps = 0;
            const Measure ms = measure(run, loop);
            for (auto [a, b] : ms.ranges)
                for (std::uint32_t pc = a; pc < b; ++pc)
                    for (const isa::Instr& in : run.prog->bundle_instrs(pc))
                        if (in.info().mnemonic == "lbu") steps += static_cast<double>(run.proc->counters().exec[pc]);
            rows.push_back(make_row("dda_step", machine, run, loop, steps, os ? 11.0 : 23.0, os ? 2.0 : 1.0, os));
            if (!os) {
                // seq: bounds per step from the x path (decision + step), the common case
                Row& r = rows.back();
                r.res_mii = 9, r.rec_mii = 4;
                r.note = "branchy: 9 ops per step";
            }
            rows.push_back(make_row("dda_init", machine, run, {"new_ray", "fast_setup", "slow_setup", "setup2"}, 0, 60.0, 1.0, false));
        }
        // sparse grid: VISITs and RETURNs
        {
            Run run(dir, file, machine);
            Grid g = make_grid(20, 0.03, rng);
            run.load(kernels::os_image(g.g, g.occ));
            run.run();
            drive_dda(run, rng, 300);
            rows.push_back(make_row("recv_ray", machine, run, {"next_ray"}, 0, 25.0, 1.0, false));
            rows.back().note = "tag word + dispatch; the 8 ray words are received inside dda_init";
            rows.push_back(make_row("send_ray", machine, run, {"visit_a", "visit_b"}, 0, 25.0, 1.0, false));
            rows.push_back(make_row("resume", machine, run, {"resume"}, 0, std::nullopt, 1.0, false));
            rows.push_back(whole_kernel_row(machine, run, 300.0,
                                            machine == "os" ? "per ray, processing cycles only; paper OS ILP "
                                                              "2.27-2.29, util 0.56-0.57"
                                                            : "per ray, processing cycles only"));
        }
    }
    for (const std::string machine : {"ic", "seq"}) {
        const bool ic = machine == "ic";
        const std::string file = ic ? "ic/intersect.s" : "seq/intersect.s";
        // ic: one straight-line body per primitive (dispatch included), A/B variants;
        // seq: the shared dispatch (next_prim) plus the kind's code with its early exits.
        const std::vector<std::string> tri = ic ? std::vector<std::string>{"tri1_A", "tri1_B"}
                                                : std::vector<std::string>{"next_prim", "tri1", "tri_common"};
        const std::vector<std::string> q1 = ic ? std::vector<std::string>{"ball1_A", "ball1_B"}
                                               : std::vector<std::string>{"next_prim", "ball1", "quad_roots", "sph_root"};
        const std::vector<std::string> q2 = ic ? std::vector<std::string>{"sph2_A", "sph2_B"}
                                               : std::vector<std::string>{"next_prim", "sph2", "quad_common", "quad_roots", "sph_root", "sph_two"};
        const std::vector<std::string> qc = ic ? std::vector<std::string>{"quad1_A", "quad1_B"}
                                               : std::vector<std::string>{"next_prim", "quad1", "quad_common", "quad_roots"};
        auto tests = [&](const Run& run, const std::vector<std::string>& first) {
            return measure(run, first).entries;
        };
        {
            const auto run_owner = run_ic(dir, file, machine, 0, 40, 200, false);
            const Run& run = *run_owner;
            const double n = tests(run, ic ? tri : std::vector<std::string>{"tri1"});
            rows.push_back(make_row("triangle", machine, run, tri, n, 50.0, 2.0, ic));
            rows.back().note = ic ? "one-sided; paper 40 + 10 shape load" : "one-sided, rays at the triangles: mean with early exits";
            rows.push_back(whole_kernel_row(machine, run, 200.0,
                                            ic ? "per ray, 40 triangles; processing only; paper IC ILP "
                                                 "2.01-2.31, util 0.50-0.57"
                                               : "per ray, 40 triangles; processing only"));
            rows.push_back(make_row("recv_ray", machine, run, {"next_ray"}, 0, 25.0, 1.0, false));
            rows.push_back(make_row("send_ray", machine, run, {"done", "hit", "return"}, 0, 25.0, 1.0, false));
        }
        {
            const auto run_owner = run_ic(dir, file, machine, 1, 40, 200, false);
            const Run& run = *run_owner;
            const double n = tests(run, ic ? q1 : std::vector<std::string>{"ball1"});
            rows.push_back(make_row("quadric_hit", machine, run, q1, n, 61.0, 2.0, ic));
            rows.back().note = ic ? "one-sided plain sphere (CODE_BALL1); branch-free: hit = miss; paper 50 + 11 load"
                                  : "one-sided plain sphere, two real roots; paper 50 + 11 load";
            const auto run2_owner = run_ic(dir, file, machine, 1, 40, 200, true);
            const Run& run2 = *run2_owner;
            const double n2 = tests(run2, ic ? q1 : std::vector<std::string>{"ball1"});
            rows.push_back(make_row("quadric_miss", machine, run2, q1, n2, std::nullopt, 2.0, ic));
            rows.back().note = "sphere, discriminant < 0";
            const auto run3_owner = run_ic(dir, file, machine, 2, 40, 200, false);
            const Run& run3 = *run3_owner;
            const double n3 = tests(run3, ic ? q2 : std::vector<std::string>{"sph2"});
            rows.push_back(make_row("quadric2_hit", machine, run3, q2, n3, 61.0, 2.0, ic));
            rows.back().note = "two-sided sphere: both roots";
            const auto run4_owner = run_ic(dir, file, machine, 3, 40, 200, false);
            const Run& run4 = *run4_owner;
            const double n4 = tests(run4, ic ? qc : std::vector<std::string>{"quad1"});
            rows.push_back(make_row("cylinder_hit", machine, run4, qc, n4, 61.0, 2.0, ic));
            rows.back().note = "one-sided quadric with axial clip (cylinder)";
        }
    }
    return rows;
}

void print(const std::vector<Row>& rows) {
    fmt::print("{:<13} {:<4} {:>8} {:>7} {:>6} {:>6} {:>6} {:>7} {:>7}  {}\n", "metric", "mach", "cycles", "paper",
               "ops", "ILP", "util", "ResMII", "RecMII", "note");
    for (const Row& r : rows) {
        const std::string paper = r.paper ? fmt::format("{:.0f}", *r.paper) : "-";
        const std::string res = r.res_mii > 0 ? fmt::format("{:.2f}", r.res_mii) : "-";
        const std::string rec = r.rec_mii > 0 ? fmt::format("{:.2f}", r.rec_mii) : "-";
        fmt::print("{:<13} {:<4} {:>8.2f} {:>7} {:>6.1f} {:>6.2f} {:>6.2f} {:>7} {:>7}  {}\n", r.metric, r.machine,
                   r.cycles, paper, r.ops, r.ilp, r.utilization, res, rec, r.note);
    }
    auto find = [&](const char* metric, const char* machine) -> const Row* {
        for (const Row& r : rows)
            if (r.metric == metric && r.machine == machine) return &r;
        return nullptr;
    };
    const Row* step = find("dda_step", "os");
    const Row* tri = find("triangle", "ic");
    const Row* quad = find("quadric_hit", "ic");
    const Row* os_all = find("whole_kernel", "os");
    const Row* ic_all = find("whole_kernel", "ic");
    if (step && tri && quad && os_all && ic_all) {
        auto mark = [](bool ok) { return ok ? "met" : "NOT met"; };
        fmt::print("\ngoals: voxel step on os <= 6: {:.2f} ({}); triangle on ic <= 20: {:.2f} ({}); quadric on ic <= 25: "
                   "{:.2f} ({}); ILP >= 3.0: os {:.2f}, ic {:.2f} ({})\n",
                   step->cycles, mark(step->cycles <= 6.0), tri->cycles, mark(tri->cycles <= 20.0), quad->cycles,
                   mark(quad->cycles <= 25.0), os_all->ilp, ic_all->ilp, mark(os_all->ilp >= 3.0 && ic_all->ilp >= 3.0));
    }
    fmt::print("\ncycles: per voxel step / ray / primitive, measured on the ISS (fast engine) from label regions;\n"
               "paper: Gwun et al. 1993 step counts (3DDDA 11 VLIW / 23 sequential, init 60, FIFO load/store 25,\n"
               "triangle 40 + 10 load, quadric 50 + 11 load); ILP = ops / cycles in the measured code; util = ILP /\n"
               "issue slots; ResMII, RecMII: lower bounds per step or primitive from the machine description.\n");
}

} // namespace

void add_kernels(CLI::App& app) {
    auto* cmd = app.add_subcommand("kernels", "Cycle report of the hand-scheduled kernels (measured on the ISS)");
    auto json = std::make_shared<std::string>();
    auto dir = std::make_shared<std::string>();
    cmd->add_option("--json", *json, "Also write the table as JSON to FILE");
    cmd->add_option("--kernels", *dir, "A folder of kernel sources to measure instead of the built-in ones");
    cmd->callback([json, dir] {
        const std::vector<Row> rows = collect(dir->empty() ? kernels::embedded() : kernels::from_directory(*dir));
        print(rows);
        if (!json->empty()) {
            nlohmann::json j;
            j["kernels"] = nlohmann::json::array();
            for (const Row& r : rows) {
                nlohmann::json e{{"metric", r.metric}, {"machine", r.machine}, {"cycles", r.cycles},
                                 {"ops", r.ops}, {"ilp", r.ilp}, {"utilization", r.utilization},
                                 {"res_mii", r.res_mii}, {"rec_mii", r.rec_mii}, {"note", r.note}};
                e["paper"] = r.paper ? nlohmann::json(*r.paper) : nlohmann::json(nullptr);
                j["kernels"].push_back(e);
            }
            std::ofstream f(*json);
            if (!f) throw CLI::RuntimeError("cannot write " + *json, 1);
            f << j.dump(2) << "\n";
        }
    });
}

} // namespace nesshi::cli
