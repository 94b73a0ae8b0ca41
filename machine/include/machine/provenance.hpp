// What a machine run's results depend on, as named strings: the tool, the scene's text, the grid,
// each kernel source, each stage's machine description and every option that can change a cycle.
// A stored result (a paper or sweep cell) keeps it, so a later run can tell whether the result is
// still its own and, when not, name what changed.
//
//   machine::Provenance p = machine::provenance("balls", 20, render_options, machine_options);
//   for (const std::string& d : machine::provenance_differences(stored, p)) ...  // "machine.ic: ..."
#pragma once

#include "machine/machine.hpp"

#include <map>
#include <string>
#include <vector>

namespace nesshi::machine {

// Keys: "tool", "build" (build_identity()), "scene", "scene.hash", "grid", "kernels.<path>" (one per source file),
// "machine.os" / "machine.ic" (model V only) and "machine.seq" ("<name> <fingerprint>"),
// "options.<name>". Only what the run uses: a model-M cell does not depend on the IC's machine.
using Provenance = std::map<std::string, std::string>;

// `scene` as the user gave it (built-in name, NAME:SIZE or NFF path: its text is hashed);
// `grid` the resolution the run uses (voxels per side). Throws what loading them throws.
Provenance provenance(const std::string& scene, int grid, const rt::RenderOptions& ro, const Options& mo);

// "key: stored -> current" for every key whose value differs or is missing on one side. "tool"
// (the version) is not compared; "build" is unless `same_build` is false (the caller keeps
// results of another build on purpose, and says so).
std::vector<std::string> provenance_differences(const Provenance& stored, const Provenance& current,
                                                bool same_build = true);

// This build's identity: a hash of the sources of every library a cycle count depends on (the
// build computes it; cmake/BuildId.cmake), so a result from an older timing model is not current.
std::string build_identity();

// The kernel cache the front ends turn on (the command line, the Python module, the machine
// tests): kbuild::enable_schedule_cache(kbuild::default_schedule_cache_dir(), build_identity()).
void enable_default_schedule_cache();

// The digest of a stored result: FNV-1a of the JSON document without its "host" (wall times) and
// "digest" members, so a hand-edited number is caught. `stats` is a JSON object.
std::string result_digest(nlohmann::json stats);

} // namespace nesshi::machine
