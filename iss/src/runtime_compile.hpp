// Compiled runs built at run time (iss/compiled.hpp: RuntimeCompile), for the programs the build
// did not compile: a user's machine, a kernel rescheduled for it, any `nesshi sim` program.
//
// A program without built-in runs gets an entry keyed by its decoded hash and size and by the
// sources the runs are compiled against (the ISS headers embedded in this binary, the emitter,
// the compiler and its flags: the build's key). Runs compiled before, by this or another process,
// are in the cache ($XDG_CACHE_HOME/nesshi/compiled/<build>/<hash>-<bundles>.so) and loaded with
// the entry. Otherwise, once the program has run kHotCycles (or at once under `wait`),
// compiled_runs_source writes its runs in parts, the system's C++ compiler builds them side by side
// at nice 10 into the cache, and the processors running it switch to them between two slices of
// their runs (Processor::dispatch). The results are those of the interpreter: a compiled run is
// the threaded chain's semantics with the operands known.
#pragma once

#include "iss/compiled.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::iss {

class Program;
struct RuntimeCompiled; // one per key, never freed

namespace detail {

// The entry of a program without built-in runs, its runs loaded when the cache has them; nullptr
// when run-time compilation is off (NESSHI_RUNTIME_COMPILE=0, or no cache folder).
RuntimeCompiled* runtime_compiled_for(uint64_t decoded_hash, uint32_t bundles);
// Its runs, or nullptr while they are not ready.
const CompiledProgram* runtime_table(const RuntimeCompiled& e);
// After a processor of `prog` ran `cycles` more: its runs when ready. The first call that finds
// the program hot starts their compilation (in the background; under `wait`, here).
const CompiledProgram* runtime_ran(RuntimeCompiled& e, const Program& prog, uint64_t cycles);

// The files the runs are compiled against, embedded at build time (cmake/EmbedFiles.cmake).
struct EmbeddedFile {
    std::string path; // from the source root: "iss/src/core.hpp"
    std::string text;
};
const std::vector<EmbeddedFile>& runtime_sources();

} // namespace detail
} // namespace nesshi::iss
