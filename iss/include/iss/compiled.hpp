// Compiled runs: straight runs of known programs compiled to C++ at build time (issue 16, step 6).
//
// The ISS knows no program: a library above it (machine/'s nesshi_compiled_runs, generated from
// the built-in kernels) registers one table per program it compiled, keyed by that program's
// Program::decoded_hash() and size. A Program finds its table at load; any other program (a user
// kernel, a kernel rescheduled for another machine, an edited source) runs on the threaded
// interpreter. NESSHI_COMPILED=0 in the environment turns compiled runs off for every program
// (set_compiled_enabled for the programs loaded after it, e.g. a benchmark comparing both in one
// run); Processor::set_compiled_runs turns them off for one processor.
#pragma once

#include <cstdint>

namespace nesshi::iss {

struct Core;
// Entry of a compiled run at bundle core.pc: it issues bundles as the threaded chain would
// (src/compiled.hpp) and returns true when control went on to another run's bundle core.pc
// (not yet issued), false when it stopped in bundle core.pc with that bundle's ops executed.
using CompiledRun = bool (*)(Core& core);

struct CompiledProgram {
    const char* name = "";            // "os/dda.s@os", for reports
    uint64_t hash = 0;                // Program::decoded_hash()
    uint32_t bundles = 0;             // Program::size()
    const CompiledRun* entry = nullptr; // by bundle: the run holding it, entered there
    const uint32_t* run_of = nullptr; // by bundle: index of its run (first bundle order)
    uint32_t runs = 0;
};

// Registers `p` (static storage); a second table with the same hash and size replaces nothing.
void register_compiled(const CompiledProgram& p);
// The registered table of a program, or nullptr (also when NESSHI_COMPILED=0).
const CompiledProgram* find_compiled(uint64_t hash, uint32_t bundles);
// Whether programs loaded from now on look their table up (default: NESSHI_COMPILED is not "0").
void set_compiled_enabled(bool on);
bool compiled_enabled();
// Compiled runs for the programs the build did not compile, built at run time with the system's
// C++ compiler (src/runtime_compile.hpp), chosen by NESSHI_RUNTIME_COMPILE:
//   unset or "1"  Background: a program that has run 2^26 cycles (about half a second) is compiled
//                 at nice 10 while it runs on the interpreter, and switches to its runs when they
//                 are ready; runs compiled before are loaded from the cache at once;
//   "wait"        Wait: compiled before its first bundle runs, the run waiting (benchmarks);
//   "wait:N"      Wait, once the program has run N cycles (tests: a switch in mid-run);
//   "0"           Off: never compiled, nothing loaded from the cache.
// The compiler is $NESSHI_CXX, else clang++ (the fastest to compile them), else the one that built
// nesshi, else `c++`; without one, programs run on the interpreter. Results never depend on the
// mode or the compiler.
enum class RuntimeCompile { Off, Background, Wait };
RuntimeCompile runtime_compile_mode();
// Off keeps the programs loaded from now on from looking for run-time runs; Background and Wait
// (compiled once the program has run `wait_after` cycles) apply to every program from now on.
void set_runtime_compile_mode(RuntimeCompile mode, uint64_t wait_after = 0);

// Every registered table, for tests.
int compiled_count();
const CompiledProgram& compiled_at(int i);

} // namespace nesshi::iss
