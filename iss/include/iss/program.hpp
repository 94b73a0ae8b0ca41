// The pre-decoded program: every bundle decoded once at load, ready for the engines.
//
// A Program is immutable and shared (std::shared_ptr<const Program>) by any number of
// Processor instances, so many processors running one kernel cost one copy of the code.
#pragma once

#include "base/error.hpp"
#include "isa/encoding.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace nesshi::iss {

struct Core;
struct DecodedOp;
struct ThreadedOp;
// One operation's semantics, specialised per opcode at compile time (see src/handlers.hpp).
using Handler = void (*)(Core& core, const DecodedOp& op);
// The same inside a threaded run (src/chain.hpp): the run's cycle and budget (Core::cycle, left)
// travel in argument registers from handler to handler, and reach the Core only at a stop.
using ThreadedHandler = void (*)(Core& core, const ThreadedOp& op, uint64_t cycle, uint64_t left);

// Register operands are flat indices into the 256-entry register array: r0..r127 are 0..127,
// f0..f127 are 128..255. Index kNoReg (256) names a scratch slot for unused operands.
inline constexpr uint16_t kNumRegs = 2 * isa::kMaxRegs;
inline constexpr uint16_t kNoReg = kNumRegs;

// An op as a threaded run reads it (Program::threaded(), indexed as Program::ops): its handler
// and the fields the hot paths read, in 32 bytes rather than DecodedOp's 72, so that a kernel's
// runs stay in the L1 cache; the rest (channel, instr) is found through `index`.
struct ThreadedOp {
    ThreadedHandler fn = nullptr;      // DecodedOp::tfn
    uint16_t dst = kNoReg, a = kNoReg, b = kNoReg, c = kNoReg;
    uint32_t imm = 0, latency = 1, index = 0, bundle = 0;
};
static_assert(sizeof(ThreadedOp) == 32);

struct DecodedOp {
    Handler fn = nullptr;              // fast engine: may write a latency-1 result in place
    Handler fn_buffered = nullptr;     // checked/traced engines: every write goes through the queue
    ThreadedHandler tfn = nullptr;     // fast engine inside a run: fn, then the rest of the run (as ThreadedOp::fn)
    uint16_t dst = kNoReg;             // destination (flat index) or kNoReg
    uint16_t a = kNoReg, b = kNoReg, c = kNoReg; // sources by field Rs1, Rs2, Rs3
    uint32_t imm = 0;
    uint32_t latency = 1;              // cycles from issue until the write lands
    uint32_t index = 0;                // index into Program::ops (for reports)
    uint32_t bundle = 0;               // bundle address
    isa::Instr instr;                  // the decoded operation, for printing
    uint32_t chan = 0;                 // send/recv: index of channel `imm` in Program::channel_ids()
    uint16_t need = 0;                 // send/recv: this op and the earlier ops of its bundle on its
                                       // channel in its direction (the words its gate asks for)
    uint16_t batch = 0;                // send/recv: the words its bundle moves in its direction when
                                       // they are more than one and all on its channel (moved in one
                                       // Channel::pop_n or push_n call), else 0
};

// A FIFO bundle's fast gate (the threaded engine's test before it chains into the bundle): per
// channel and direction the bundle uses, in the order of their first op in Program::ops, the
// words it receives from (readable) or sends into (writable) that channel.
struct FifoNeed {
    uint32_t slot = 0;                 // DecodedOp::chan
    uint32_t need = 0;
    bool recv = false;
};

// Static properties of a bundle; dynamic behaviour only needs its execution count.
struct DecodedBundle {
    uint32_t first = 0, count = 0;     // range in Program::ops (stores placed last)
    uint32_t ops = 0;                  // non-nop operations
    bool fifo = false;                 // contains send/recv: a communication cycle
    bool slow = false;                 // needs the engine's slow path (FIFO gate)
    bool control = false;              // branch, jump or halt
    // Fast engine: this bundle and the run - 1 after it issue back to back unless a handler
    // raises an event or a FIFO bundle's fast gate does not pass (none but the last has control).
    uint32_t run = 1;
    std::array<uint32_t, isa::kNumRegFiles> reads{};
    std::array<uint32_t, isa::kNumRegFiles> writes{};
    std::array<uint32_t, isa::kNumRegFiles> lat1_writes{}; // writes that land in the next cycle
    uint32_t slot_mask = 0;            // bit s: slot s issues a non-nop operation
    uint32_t gate_first = 0, gate_count = 0; // FIFO bundles: range in Program::fifo_needs()
};

// A code label region: from a label's bundle to the next label's bundle (exclusive).
struct Region {
    std::string label;
    uint32_t first = 0, end = 0;
};

// A loading problem: illegal encoding, bundle that breaks a static rule, data outside memory.
class LoadError : public base::Error {
  public:
    using base::Error::Error;
};

class Program {
  public:
    // Decodes and statically checks `obj` for machine `m` (every data section inside a memory
    // region included). Throws LoadError.
    Program(const isa::ObjectFile& obj, const isa::Machine& m);

    const isa::Machine& machine() const { return machine_; }
    const isa::ObjectFile& object() const { return object_; }
    const std::vector<DecodedBundle>& bundles() const { return bundles_; }
    const std::vector<DecodedOp>& ops() const { return ops_; }
    const std::vector<ThreadedOp>& threaded() const { return threaded_; } // the ops' threaded form
    const std::vector<Region>& regions() const { return regions_; }
    // The channel ids the program's send/recv operations use, ascending, each once.
    const std::vector<uint32_t>& channel_ids() const { return channel_ids_; }
    // The fast gates of the FIFO bundles (DecodedBundle::gate_first, gate_count).
    const std::vector<FifoNeed>& fifo_needs() const { return fifo_needs_; }
    uint32_t size() const { return uint32_t(bundles_.size()); }
    // The ops of bundle `pc` in slot order (as written), for printing.
    std::vector<isa::Instr> bundle_instrs(uint32_t pc) const;

    // Symbols: code labels resolve to bundle addresses, data labels to byte addresses.
    const isa::Symbol* find_symbol(std::string_view name) const;
    // "label" or "label+3" for a bundle address; empty when no label precedes it.
    std::string code_name(uint32_t pc) const;
    // The label whose region contains pc, or -1.
    int region_of(uint32_t pc) const { return pc < region_index_.size() ? region_index_[pc] : -1; }
    // "file:line" of bundle pc, or empty.
    std::string source_of(uint32_t pc) const;
    // "{ iu0: add r1, r2, r3 ; fpu0: fadd f1, f2, f3 }", branch targets named by label.
    std::string format_bundle(uint32_t pc) const;
    std::string format_op(const isa::Instr& in) const;

    // A hash of everything the fast engine's form of the program depends on (each op's opcode,
    // registers, immediate, latency, channel, FIFO need and in-place write; each bundle's shape
    // and FIFO gate; the machine's fingerprint): the key of a compiled-run table (iss/compiled.hpp).
    uint64_t decoded_hash() const { return hash_; }
    // This program's compiled runs: the build's, else those compiled at run time once they are
    // ready (src/runtime_compile.hpp); nullptr when it has neither (yet).
    const struct CompiledProgram* compiled() const;
    // The run-time entry of a program without built-in runs, or nullptr (compilation off).
    struct RuntimeCompiled* runtime_compiled() const { return runtime_; }

  private:
    isa::Machine machine_;
    isa::ObjectFile object_;
    std::vector<DecodedBundle> bundles_;
    std::vector<DecodedOp> ops_;
    std::vector<ThreadedOp> threaded_;
    std::vector<Region> regions_;
    std::vector<uint32_t> channel_ids_;
    std::vector<FifoNeed> fifo_needs_;
    std::vector<int> region_index_;
    std::vector<const isa::Symbol*> code_labels_; // sorted by address
    std::vector<std::vector<isa::Instr>> original_; // bundles as written (slot order)
    uint64_t hash_ = 0;
    const struct CompiledProgram* compiled_ = nullptr;
    struct RuntimeCompiled* runtime_ = nullptr;
};

std::shared_ptr<const Program> load_program(const isa::ObjectFile& obj, const isa::Machine& m);
// Reads the object and the machine it names (or `machine_override` when not empty). An object for
// a machine that is not a preset (assembled with -m FILE) needs the override; with or without
// it, the object's fingerprint must match the machine's (LoadError).
std::shared_ptr<const Program> load_program_file(const std::string& path,
                                                 const std::string& machine_override = {});

// Flat register index helpers and names ("r5", "f12").
constexpr uint16_t flat_reg(isa::RegFile f, uint32_t n) {
    return uint16_t(static_cast<int>(f) * isa::kMaxRegs + n);
}
std::string reg_name(uint16_t flat);

} // namespace nesshi::iss
