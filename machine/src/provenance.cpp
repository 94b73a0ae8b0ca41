// The provenance of a machine run and the digest of a stored result.
#include "machine/provenance.hpp"

#include "build_id.hpp" // generated: NESSHI_BUILD_ID

#include "base/hash.hpp"
#include "base/read_file.hpp"
#include "kbuild/schedule_cache.hpp"
#include "isa/machine.hpp"
#include "kernels/sources.hpp"
#include "rt/spd.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#ifndef NESSHI_VERSION
#error "NESSHI_VERSION must be defined by the build"
#endif

namespace nesshi::machine {

namespace {

std::string scene_text(const std::string& scene) {
    if (const auto spd = rt::parse_spd_name(scene)) return rt::generate_spd(spd->name, spd->size);
    return base::read_file(scene);
}

std::string machine_id(const kbuild::StageMachine& s) { return fmt::format("{} {}", s.reference(), base::hex64(s.machine().fingerprint())); }

} // namespace

Provenance provenance(const std::string& scene, int grid, const rt::RenderOptions& ro, const Options& mo) {
    Provenance p;
    p["tool"] = "nesshi " NESSHI_VERSION;
    p["build"] = NESSHI_BUILD_ID;
    p["stats_schema"] = std::to_string(rt::kStatsSchema); // a cell of another layout is read again from a new run
    p["scene"] = scene;
    p["scene.hash"] = base::hex64(base::fnv1a64(scene_text(scene)));
    p["grid"] = std::to_string(grid);
    const kernels::SourceSet src = mo.kernels_dir.empty() ? kernels::embedded() : kernels::from_directory(mo.kernels_dir);
    for (const kernels::SourceFile& f : src.files) p["kernels." + f.path] = base::hex64(base::fnv1a64(f.text));
    if (mo.model == Model::V) { // models S and M run both kernels on seq
        p["machine.os"] = machine_id(mo.os_machine);
        p["machine.ic"] = machine_id(mo.ic_machine);
    }
    p["machine.seq"] = machine_id(mo.seq_machine); // also the SC's operation prices
    auto opt = [&](const char* name, const auto& value) { p[std::string("options.") + name] = fmt::format("{}", value); };
    opt("model", model_name(mo.model));
    opt("size", fmt::format("{}x{}", ro.width, ro.height));
    opt("max_depth", ro.max_depth);
    opt("epsilon", ro.epsilon);
    opt("cutoff", ro.cutoff);
    opt("pes", mo.pes);
    opt("balance", mo.dynamic_balance ? fmt::format("dynamic, epoch {}", mo.epoch) : std::string("interleaved"));
    opt("window", mo.window);
    opt("fifo_capacity", mo.fifo_capacity);
    opt("ray_slots", mo.ray_slots);
    opt("fifo_latency", mo.fifo_latency);
    opt("quantum", mo.effective_quantum());
    opt("cache", mo.cache.enabled ? fmt::format("{} bytes, {}-byte lines, {} ways, {} miss cycles", mo.cache.bytes,
                                                mo.cache.line, mo.cache.ways, mo.cache.miss_cycles)
                                  : std::string("ideal"));
    opt("resident", mo.resident);
    opt("max_cycles", mo.max_cycles);
    return p;
}

std::vector<std::string> provenance_differences(const Provenance& stored, const Provenance& current, bool same_build) {
    std::vector<std::string> d;
    auto value = [](const Provenance& p, const std::string& k) {
        const auto it = p.find(k);
        return it == p.end() ? std::string("(none)") : it->second;
    };
    std::map<std::string, int> keys;
    for (const auto& [k, v] : stored) keys[k] |= 1;
    for (const auto& [k, v] : current) keys[k] |= 2;
    for (const auto& [k, sides] : keys) {
        // A cycle limit changes no result that finished under it, the quantum no result at all;
        // the others all do.
        if (k == "tool" || k == "options.max_cycles" || k == "options.quantum" || (k == "build" && !same_build)) continue;
        const std::string a = value(stored, k), b = value(current, k);
        if (a != b) d.push_back(fmt::format("{}: {} -> {}", k, a, b));
    }
    return d;
}

std::string build_identity() { return NESSHI_BUILD_ID; }

void enable_default_schedule_cache() {
    kbuild::enable_schedule_cache(kbuild::default_schedule_cache_dir(), build_identity());
}

std::string result_digest(nlohmann::json stats) {
    stats.erase("host");
    stats.erase("digest");
    return base::hex64(base::fnv1a64(stats.dump()));
}

} // namespace nesshi::machine
