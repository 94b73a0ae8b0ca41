// Compiled runs (iss/compiled.hpp) and the threaded interpreter against the general loop, in
// lock-step: every built-in kernel on grids and primitive workloads, with and without caches
// (memory stalls, and the cycle a cache model sees) and a bad voxel (a memory fault), three
// processors compared after every step of a varying number of bundles.
#include "kbuild/synthetic_inputs.hpp"
#include "kbuild/runner.hpp"

#include "base/vec.hpp"
#include "iss/cache.hpp"
#include "iss/compiled.hpp"
#include "iss/compiled_emit.hpp"
#include "kernels/abi.hpp"
#include "kernels/image.hpp"
#include "kernels/messages.hpp"
#include "kernels/shape_record.hpp"
#include "kernels/twins/dda.hpp"

#include <catch2/catch.hpp>
#include <fmt/core.h>

#include <array>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace nesshi;

namespace {

// The full state two processors must share after the same steps.
std::string differ(const iss::Processor& a, const iss::Processor& b) {
    if (a.status() != b.status()) return "status";
    if (a.status() == iss::Status::Faulted &&
        (a.fault()->kind != b.fault()->kind || a.fault()->cycle != b.fault()->cycle || a.fault()->pc != b.fault()->pc ||
         a.fault()->message != b.fault()->message))
        return "fault";
    if (a.pc() != b.pc()) return fmt::format("pc {} vs {}", a.pc(), b.pc());
    if (a.cycle() != b.cycle()) return fmt::format("cycle {} vs {}", a.cycle(), b.cycle());
    for (uint16_t r = 0; r < iss::kNumRegs; ++r)
        if (a.reg(r) != b.reg(r)) return "register " + iss::reg_name(r);
    const auto ia = a.inflight(), ib = b.inflight();
    if (ia.size() != ib.size()) return "in-flight count";
    for (size_t i = 0; i < ia.size(); ++i)
        if (ia[i].reg != ib[i].reg || ia[i].value != ib[i].value || ia[i].lands != ib[i].lands || ia[i].op != ib[i].op)
            return "in-flight write";
    const iss::Counters &ka = a.counters(), &kb = b.counters();
    if (ka.exec != kb.exec) return "exec counts";
    if (ka.taken != kb.taken) return "taken counts";
    if (ka.stall != kb.stall || ka.wait != kb.wait) return "stall or wait counts";
    if (ka.wait_cycles != kb.wait_cycles || ka.bubble_cycles != kb.bubble_cycles || ka.stall_cycles != kb.stall_cycles)
        return "cycle counters";
    if (ka.words_received != kb.words_received || ka.words_sent != kb.words_sent) return "word counts";
    for (int f = 0; f < isa::kNumRegFiles; ++f)
        if (a.write_histogram(f) != b.write_histogram(f)) return "write histogram";
    return {};
}

// A cache that also hashes its processor's cycle() at every access: a host's model may ask for
// it, and every engine must then give the access's issue cycle (runs keep it out of the core).
struct CycleCache : iss::CacheModel {
    iss::SetAssocCache inner{iss::CacheGeometry{2048, 32, 2, 9}};
    const iss::Processor* proc = nullptr;
    uint64_t accesses = 0, hash = 0;
    uint32_t access(uint32_t addr, uint32_t bytes, bool write) override {
        ++accesses;
        hash = hash * 1099511628211ull + proc->cycle();
        return inner.access(addr, bytes, write);
    }
};

// A tracer makes the fast engine take the general loop, one bundle per turn (no runs at all).
struct NullTracer : iss::Tracer {
    void on_cycle(const iss::Program&, const iss::CycleEvent&) override {}
};

// Three runners of one program, fed alike and stepped alike: A with compiled runs, B threaded
// without them, G on the general loop (the reference both are held to).
struct Pair {
    std::shared_ptr<const iss::Program> prog;
    kbuild::KernelRunner a, b, g;
    NullTracer tracer;
    std::vector<std::unique_ptr<CycleCache>> caches; // per memory: A's, B's, G's
    std::mt19937 steps{11};
    uint64_t fixed_step = 0; // when not 0, every step is this many bundles
    uint64_t compared = 0;
    std::vector<uint32_t> out1, out2; // what the three sent up to the last run()'s return

    Pair(std::shared_ptr<const iss::Program> p, bool cache) : prog(p), a(p), b(p), g(p) {
        b.proc->set_compiled_runs(false);
        g.proc->set_compiled_runs(false);
        g.proc->set_tracer(&tracer);
        REQUIRE(a.proc->compiled_runs());
        REQUIRE_FALSE(b.proc->compiled_runs());
        if (cache)
            for (const auto& m : prog->machine().memories)
                for (kbuild::KernelRunner* r : {&a, &b, &g}) {
                    caches.push_back(std::make_unique<CycleCache>());
                    caches.back()->proc = r->proc.get();
                    r->proc->attach_cache(m.name, caches.back().get());
                }
    }
    std::string differ_caches() const {
        for (size_t i = 0; i < caches.size(); i += 3)
            for (size_t j : {i + 1, i + 2})
                if (caches[i]->accesses != caches[j]->accesses || caches[i]->hash != caches[j]->hash)
                    return fmt::format("the cycles a cache model saw ({} accesses vs {})", caches[i]->accesses,
                                       caches[j]->accesses);
        return {};
    }
    void load(const kernels::MemImage& m) {
        a.load(m);
        b.load(m);
        g.load(m);
    }
    template <class Words> void feed(const Words& w) {
        a.feed(w);
        b.feed(w);
        g.feed(w);
    }
    // Until both wait for input (or halt or fault), in steps of 1 to 5000 bundles: small ones stop
    // runs at every offset, also between a ring push and its landing (compiled.hpp's Land).
    iss::Status run() {
        static constexpr std::array<uint64_t, 12> kSteps{1, 2, 3, 4, 5, 7, 11, 20, 64, 300, 5000, 1};
        for (;;) {
            const uint64_t n = fixed_step ? fixed_step : kSteps[steps() % kSteps.size()];
            const iss::Status sa = a.proc->step(n, 1'000'000);
            const iss::Status sb = b.proc->step(n, 1'000'000);
            const iss::Status sg = g.proc->step(n, 1'000'000);
            ++compared;
            const char* file = prog->object().files.empty() ? "" : prog->object().files[0].c_str();
            for (const auto& [name, d] : {std::pair{"compiled and the general loop", differ(*a.proc, *g.proc)},
                                          std::pair{"threaded and the general loop", differ(*b.proc, *g.proc)},
                                          std::pair{"the engines", differ_caches()}})
                if (!d.empty())
                    FAIL(fmt::format("{}: {} differ after step {} ({} bundles): {}", file, name, compared, n, d));
            REQUIRE(sg == sb);
            REQUIRE(sa == sb);
            if (sa == iss::Status::Faulted || sa == iss::Status::Halted ||
                (sa == iss::Status::Blocked && a.proc->blocked_channel() == 0)) {
                REQUIRE(a.proc->memory().hash() == g.proc->memory().hash());
                REQUIRE(b.proc->memory().hash() == g.proc->memory().hash());
                out1 = g.out1.drain_all();
                out2 = g.out2.drain_all();
                REQUIRE(a.out1.drain_all() == out1);
                REQUIRE(b.out1.drain_all() == out1);
                REQUIRE(a.out2.drain_all() == out2);
                REQUIRE(b.out2.drain_all() == out2);
                return sa;
            }
        }
    }
};

// The 3DDDA kernel: random rays; each VISIT answered by a RETURN (no hit), or, for every fifth
// ray, the first one answered with the RETURN of a hit at t = 1.
void drive_dda(Pair& p, std::mt19937& rng, int rays) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    p.run();
    for (int i = 0; i < rays; ++i) {
        base::Vec3f o{u(rng) * 30.0f, u(rng) * 30.0f, u(rng) * 30.0f};
        base::Vec3f tgt{u(rng) * 8.0f, u(rng) * 8.0f, u(rng) * 8.0f};
        if (i % 7 == 3) o = tgt * 0.5f; // from inside the grid
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::NewRay nr{kernels::abi::Tag{static_cast<std::uint32_t>(i % 4096), kernels::abi::Kind::eye, 1}.word(),
                                {o.x, o.y, o.z}, {d.x, d.y, d.z}, 0.0f, std::numeric_limits<float>::infinity()};
        p.feed(nr.words());
        for (;;) {
            REQUIRE(p.run() == iss::Status::Blocked);
            const std::vector<uint32_t> w = p.out1;
            if (w.empty()) break;
            p.feed(std::array<std::uint32_t, 1>{w[0]});
        }
    }
}

constexpr int kIntersectLists = 7;

// The intersection kernel: voxels holding triangles, spheres (one- and two-sided) and
// cylinders; rays aimed at the origin or past it. With `fault`, a last VISIT names a voxel far
// outside the lists.
iss::Status drive_intersect(Pair& p, std::mt19937& rng, int rays, bool fault) {
    std::vector<kernels::Shape> shapes;
    for (int i = 0; i < 24; ++i) shapes.push_back(i % 4 == 0   ? kbuild::random_triangle(rng, i % 8 == 0)
                         : i % 4 == 3 ? kbuild::random_cylinder(rng)
                                      : kbuild::random_sphere(rng, i % 4 == 2));
    // Lists of 1 to 6 shapes of each kind (and all 24): every exit of a per-kind loop kernel's
    // unrolled copies is taken somewhere.
    std::vector<std::vector<std::uint32_t>> lists(kIntersectLists);
    for (int v = 0; v < kIntersectLists; ++v)
        for (int i = 0; i < 24; ++i)
            if (i / 4 <= v % 6 || v == kIntersectLists - 1) lists[static_cast<std::size_t>(v)].push_back(static_cast<std::uint32_t>(i));
    const kernels::IcImage im = kernels::ic_image_lists(lists, shapes, true, kbuild::list_layout(*p.prog));
    p.load(im.resident);
    p.load(im.global);
    p.run();
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i <= rays; ++i) {
        base::Vec3f o{u(rng) * 20.0f, u(rng) * 20.0f, 20.0f};
        base::Vec3f tgt = i % 5 == 4 ? base::Vec3f{30.0f, 30.0f, 0.0f} : base::Vec3f{u(rng) * 0.3f, u(rng) * 0.3f, 0.0f};
        base::Vec3f d = base::normalize(tgt - o);
        kernels::abi::Visit v;
        v.tag = kernels::abi::Tag{static_cast<std::uint32_t>(i), kernels::abi::Kind::eye, 1}.word() |
                (i % 2 ? kernels::abi::kTagReturn : 0u);
        v.voxel = i == rays ? (fault ? 0x3fffffffu : 0u) : static_cast<std::uint32_t>(i % kIntersectLists);
        v.t_out = 1e30f;
        for (int k = 0; k < 3; ++k) v.o[k] = o[k], v.d[k] = d[k];
        v.tmax = std::numeric_limits<float>::infinity();
        p.feed(v.words());
        const iss::Status s = p.run();
        if (s != iss::Status::Blocked) return s;
    }
    return iss::Status::Blocked;
}

// Runs of each compiled program with a bundle issued by a processor with compiled runs.
std::map<std::string, std::set<uint32_t>>& reached() {
    static std::map<std::string, std::set<uint32_t>> r;
    return r;
}
void note_reached(const Pair& p) {
    const iss::CompiledProgram* c = p.prog->compiled();
    REQUIRE(c);
    auto& s = reached()[c->name];
    for (uint32_t pc = 0; pc < p.prog->size(); ++pc)
        if (p.a.proc->counters().exec[pc]) s.insert(c->run_of[pc]);
}

const std::vector<std::string> kDda = {"os/dda.s@os", "seq/dda.s@seq", "os/dda.s@os-real", "seq/dda.s@seq-real"};
const std::vector<std::string> kIntersect = {"ic/intersect.s@ic", "ic/intersect.loops.pk@ic", "seq/intersect.s@seq",
                                             "seq/intersect.s@seq-real"};

std::shared_ptr<const iss::Program> program(const std::string& spec) {
    const size_t at = spec.find('@');
    const std::string kernel = spec.substr(0, at), m = spec.substr(at + 1);
    return kernel.ends_with(".pk") ? kbuild::assemble_source(kernels::embedded(), kernel, m)
                                   : kbuild::assemble_kernel(kernels::embedded(), kernel, m);
}

void lockstep_dda() {
    for (const std::string& spec : kDda)
        for (bool cache : {false, true}) {
            INFO(spec << (cache ? " with caches" : ""));
            Pair p(program(spec), cache);
            std::mt19937 rng(5);
            const kbuild::OccupancyGrid g = kbuild::random_grid(12, 0.0, rng);
            p.load(kernels::os_image(g.g, g.occ));
            drive_dda(p, rng, 25);
            note_reached(p);
            Pair q(program(spec), cache);
            const kbuild::OccupancyGrid s = kbuild::random_grid(10, 0.05, rng);
            q.load(kernels::os_image(s.g, s.occ));
            drive_dda(q, rng, 40);
            note_reached(q);
        }
}

void lockstep_intersect() {
    for (const std::string& spec : kIntersect)
        for (bool cache : {false, true})
            for (bool fault : {false, true}) {
                INFO(spec << (cache ? " with caches" : "") << (fault ? ", bad voxel" : ""));
                Pair p(program(spec), cache);
                std::mt19937 rng(7);
                const iss::Status s = drive_intersect(p, rng, 40, fault);
                CHECK(s == (fault ? iss::Status::Faulted : iss::Status::Blocked));
                note_reached(p);
            }
}

} // namespace

TEST_CASE("compiled runs: every built-in kernel in lock-step with the interpreter, every run entered or listed",
          "[compiled]") {
    lockstep_dda();
    lockstep_intersect();
    std::string unreached;
    int total = 0, hit = 0;
    for (int i = 0; i < iss::compiled_count(); ++i) {
        const iss::CompiledProgram& c = iss::compiled_at(i);
        const auto& s = reached()[c.name];
        total += int(c.runs);
        hit += int(s.size());
        for (uint32_t r = 0; r < c.runs; ++r) {
            if (s.count(r)) continue;
            uint32_t first = 0;
            while (c.run_of[first] != r) ++first;
            unreached += fmt::format(" {}:run{}@{}", c.name, r, first);
        }
    }
    WARN(fmt::format("compiled runs entered in lock-step: {} of {}; not reached:{}", hit, total, unreached));
    CHECK(iss::compiled_count() == NESSHI_COMPILED_PROGRAMS); // the build's list (machine/CMakeLists.txt)
    CHECK(hit * 10 >= total * 7);
}

// The kernels driven above carry every form the generator emits for a bundle's end and its
// results (compiled.hpp), so that the lock-step tests, which stop in every bundle, check each:
// a change to the generator that stopped emitting one would leave it unchecked. (Ring<R...>, a
// known slot of results that are not held, needs a link or receive result of latency 2 or more:
// no built-in kernel has one; tests/cli/runtime_compile.py runs one, a 2-cycle receive.)
TEST_CASE("compiled runs: the kernels in lock-step use every landing the generator emits", "[compiled]") {
    std::string all;
    for (const auto* list : {&kDda, &kIntersect})
        for (const std::string& spec : *list)
            for (const std::string& f : iss::compiled_runs_source(*program(spec), spec, "t", 1, "t")) all += f;
    for (const char* form : {"Expect<", "NoRing>", "Probe>", "= val<", "cexit(", "cflush(", "clocal<",
                             "land_before(", " defer(c, w", "jump_to<", "jump<", "n.lasts_to(", "jump_held<false>(",
                             ", false>(c, n, "}) {
        INFO(form);
        CHECK(all.find(form) != std::string::npos);
    }
}

// Steps of one size, each size from 1 to 40 bundles: a run entered at its first bundle (its copy
// with static ring landings, compiled.hpp's Ring) stops at every offset, also between a push and
// its landing, and the next step enters the same run in the middle. Every built-in kernel, with
// caches (stalls, and the cycle a cache model sees) at every other size.
TEST_CASE("compiled runs: stopped at every offset of their runs", "[compiled]") {
    for (uint64_t step = 1; step <= 40; ++step) {
        const bool cache = step % 2 == 0;
        INFO("steps of " << step << (cache ? " with caches" : ""));
        for (const std::string& spec : kIntersect) {
            INFO(spec);
            Pair p(program(spec), cache);
            p.fixed_step = step;
            std::mt19937 rng(step);
            CHECK(drive_intersect(p, rng, 3, false) == iss::Status::Blocked);
        }
        for (const std::string& spec : kDda) {
            INFO(spec);
            Pair q(program(spec), cache);
            q.fixed_step = step;
            std::mt19937 rng(step);
            const kbuild::OccupancyGrid g = kbuild::random_grid(8, 0.05, rng);
            q.load(kernels::os_image(g.g, g.occ));
            drive_dda(q, rng, 3);
        }
    }
}

TEST_CASE("compiled runs: a program one immediate away from a compiled one runs interpreted", "[compiled]") {
    const kernels::SourceSet src = kernels::embedded();
    const auto same = kbuild::assemble_kernel(src, "ic/intersect.s", "ic");
    REQUIRE(same->compiled());
    kernels::SourceSet edited = src;
    bool changed = false;
    for (kernels::SourceFile& f : edited.files)
        if (f.path == "ic/intersect.s") {
            const size_t at = f.text.find("li r60, 0x7f800000");
            REQUIRE(at != std::string::npos);
            f.text.replace(at, 18, "li r60, 0x7f800001");
            changed = true;
        }
    REQUIRE(changed);
    const auto other = kbuild::assemble_kernel(edited, "ic/intersect.s", "ic");
    CHECK(other->size() == same->size());
    CHECK(other->decoded_hash() != same->decoded_hash());
    CHECK(other->compiled() == nullptr);
    iss::Processor proc(other);
    CHECK_FALSE(proc.compiled_runs());
    // Rescheduled for another machine: not compiled either.
    CHECK(kbuild::assemble_kernel(src, "ic/intersect.s", std::string(NESSHI_TEST_DATA) + "/ic-2iu.toml")->compiled() ==
          nullptr);
}
