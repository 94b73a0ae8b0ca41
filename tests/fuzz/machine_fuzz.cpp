// Fuzz target `machine`: TOML machine-description text through the parser; on a machine it
// accepts, a small sequential program is list-scheduled (sched::pack_source), assembled, loaded
// and run on both engines in lock-step. Bad input is a MachineError, never a crash; a machine
// the scheduler can bundle for must assemble, load and run that program to its halt.
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "iss/fault.hpp"
#include "iss/lockstep.hpp"
#include "iss/processor.hpp"
#include "sched/block.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

using namespace nesshi;

namespace {

// One of each unit class but FIFO and branch, in one block the list scheduler bundles.
constexpr std::string_view kBody = R"(#pack begin
        li r1, buf
        li r2, 3
        fli f1, 1.5
        flw f2, 0(r1)
        lw r3, 4(r1)
        add r4, r2, r3
        mul r5, r4, r2
        fadd f3, f1, f2
        fmul f4, f3, f1
        fdiv f5, f4, f1
        fsw f5, 8(r1)
        sw r5, 12(r1)
        halt
#pack end
)";

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool verbose = std::getenv("NESSHI_FUZZ_VERBOSE") != nullptr; // say how far each input got
    isa::Machine m;
    try {
        // No directory: `inherits` names a preset, or a file that is not there.
        m = isa::parse_machine(std::string_view(reinterpret_cast<const char*>(data), size), "/nonexistent/fuzz.toml");
    } catch (const isa::MachineError& e) {
        if (verbose) std::fprintf(stderr, "rejected: %s\n", e.what());
        return 0;
    }
    (void)m.fingerprint();
    if (m.memories.empty() || m.memories.front().size < 16) return 0;
    const std::string linear =
        fmt::format("        .data 0x{:x}\nbuf:    .space 16\n        .text\n{}", m.memories.front().base, kBody);
    std::string packed;
    try {
        packed = sched::pack_source(linear, "fuzz.s", m).text;
    } catch (const base::Error& e) {
        if (verbose) std::fprintf(stderr, "%s: not scheduled: %s\n", m.name.c_str(), e.what());
        return 0; // no unit for one of the operations, too few registers, ...
    }
    const assembler::AsmResult r = assembler::assemble_string(packed, "fuzz.s", m, {});
    fuzz::check(r.ok, "the list scheduler's bundles assemble", packed + r.diagnostics);
    std::shared_ptr<const iss::Program> prog;
    try {
        prog = iss::load_program(r.object, m);
    } catch (const base::Error& e) {
        fuzz::fail("an assembled program loads", packed + e.what());
    }
    iss::Processor fast(prog, iss::Engine::Fast), checked(prog, iss::Engine::Checked);
    const iss::LockstepResult ls = iss::run_lockstep(fast, checked, 100'000);
    if (verbose) std::fprintf(stderr, "%s: %s after %llu bundles\n", m.name.c_str(), iss::status_name(ls.status).data(),
                              static_cast<unsigned long long>(ls.bundles));
    fuzz::check(ls.status == iss::Status::Halted && !ls.fault, "the program runs to its halt",
                packed + (ls.fault ? iss::format_fault(*prog, *ls.fault) : std::string("no halt")));
    return 0;
}
