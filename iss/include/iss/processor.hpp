// The embedding API: one simulated processor (OS, IC or sequential) running one program.
//
//   auto prog = iss::load_program(obj, isa::load_machine("ic"));
//   iss::Processor p(prog);
//   iss::QueueChannel in, out;
//   p.attach_channel(0, &in);                    // channel numbers as used by recv/send
//   p.attach_channel(1, &out);
//   p.attach_memory("global", shared_global);    // host-owned, shared by every IC
//   while (p.run_until(p.cycle() + 1000) == iss::Status::Running) {}
//   iss::Stats s = iss::compute_stats(p);
//
// Deterministic: the same program, inputs and calls give the same cycles and state. Cheap:
// the program is shared, memory is paged on demand, registers are 1 KiB.
#pragma once

#include "iss/channel.hpp"
#include "iss/fault.hpp"
#include "iss/memory.hpp"
#include "iss/program.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace nesshi::iss {

enum class Engine : uint8_t {
    Fast,    // trusts the assembler's static checks; traps only memory, PC and channel faults
    Checked, // also checks in-flight reads, write ports and duplicate writes per landing cycle
};

enum class Status : uint8_t {
    Running, // stopped at the requested cycle or bundle count; can continue
    Blocked, // a FIFO operation cannot proceed (empty recv / full send); call run again later
    Halted,  // executed `halt`
    Faulted, // see fault()
};
std::string_view status_name(Status s);

// A write in flight: lands (becomes visible) at the start of cycle `lands`.
struct PendingWrite {
    uint16_t reg = 0;   // flat register index (see program.hpp)
    uint32_t value = 0;
    uint64_t lands = 0;
    uint32_t op = 0;    // index into Program::ops() of the producer
};

// Raw counters, cheap enough to be always on. Stats (stats.hpp) derives every view from them.
struct Counters {
    std::vector<uint64_t> exec;   // per bundle: times issued
    std::vector<uint64_t> wait;   // per bundle: cycles blocked before issuing (FIFO)
    std::vector<uint64_t> taken;  // per bundle: taken control transfers
    std::vector<uint64_t> stall;  // per bundle: memory stall cycles (extra latency, cache)
    uint64_t wait_cycles = 0, bubble_cycles = 0, stall_cycles = 0;
    uint64_t words_received = 0, words_sent = 0;
    // The write-port histogram less what the execution counts imply: each issued bundle counts
    // as one cycle in which its latency-1 writes land (exact unless longer-latency writes land
    // in the same cycle, or nothing was issued the cycle before); this holds the corrections,
    // modulo 2^64. Use Processor::write_histogram for the histogram itself.
    std::array<std::vector<uint64_t>, isa::kNumRegFiles> write_adjust;
};

// Observer of every cycle (trace.hpp implements text and Chrome trace-event writers).
struct CycleEvent {
    enum What : uint8_t { Issue, Wait, Bubble } what = Issue;
    uint64_t cycle = 0;
    uint32_t pc = 0;                          // bundle issued, or waiting to issue
    const std::vector<PendingWrite>* landed;  // writes that landed at the start of this cycle
};
class Tracer {
  public:
    virtual ~Tracer() = default;
    virtual void on_cycle(const Program& prog, const CycleEvent& ev) = 0;
};

struct Core; // engine state (src/core.hpp)

class Processor {
  public:
    explicit Processor(std::shared_ptr<const Program> prog, Engine engine = Engine::Fast);
    Processor(const Processor&) = delete;
    Processor& operator=(const Processor&) = delete;
    ~Processor();

    const Program& program() const { return *prog_; }
    std::shared_ptr<const Program> program_ptr() const { return prog_; }
    Engine engine() const { return engine_; }
    void set_engine(Engine e);
    void set_tracer(Tracer* t) { tracer_ = t; } // not owned; nullptr to stop tracing
    // Compiled runs (iss/compiled.hpp): on by default when the program has them; off, the fast
    // engine runs the threaded interpreter (same results; for lock-step and benchmarks).
    void set_compiled_runs(bool on);
    bool compiled_runs() const;

    // Connections. Channels are not owned; channel ids are those used by send/recv (any 32-bit
    // id: the table is sparse, so attaching channel 500000000 costs what attaching channel 1 does).
    void attach_channel(uint32_t id, Channel* ch);
    Channel* channel(uint32_t id) const;
    // Replace a region's storage (e.g. the shared global memory of all IC processors).
    // Throws std::invalid_argument when the region does not exist or the sizes differ.
    void attach_memory(std::string_view region, std::shared_ptr<PagedMemory> store);
    void attach_cache(std::string_view region, CacheModel* cache);
    // write_histogram(file)[n]: cycles in which n writes landed in that register file.
    std::vector<uint64_t> write_histogram(int file) const;
    MemorySystem& memory() { return *mem_; }
    const MemorySystem& memory() const { return *mem_; }

    // Running. Each returns the status at the stop.
    Status run_until(uint64_t cycle);  // stop when cycle() reaches `cycle` (blocked: waits to it)
    Status run(uint64_t max_cycles = std::numeric_limits<uint64_t>::max()); // until halt/block/fault
    // Issue `bundles` bundles (waits and bubbles included), or stop after `max_cycles` cycles even
    // in the middle of a wait (status Running, the waiting bundle not issued yet).
    Status step(uint64_t bundles = 1, uint64_t max_cycles = std::numeric_limits<uint64_t>::max());
    // Host-imposed idle time (a processor time-shared with others, or a sender held until its
    // full FIFO drains): the clock advances to `cycle`, counted as wait cycles of the current
    // bundle. No-op when `cycle` <= cycle().
    void idle_until(uint64_t cycle);

    Status status() const { return status_; }
    const std::optional<Fault>& fault() const { return fault_; }
    std::string fault_report() const; // empty when no fault
    // Inline: the machine's turn rule asks both at every switch of stage (they point into the core).
    uint64_t cycle() const { return *cycle_at_; }
    uint32_t pc() const { return *pc_at_; }
    // The channel a Blocked processor waits on.
    uint32_t blocked_channel() const { return blocked_channel_; }

    // Architectural state.
    uint32_t reg(uint16_t flat) const;
    void set_reg(uint16_t flat, uint32_t value);
    std::vector<PendingWrite> inflight() const; // sorted by landing cycle
    // The execution counts of bundles finished inside threaded chains are kept per pass (see
    // flush_passes) and added in here, so the counts are always whole when read.
    const Counters& counters() const {
        if (passes_dirty_) flush_passes();
        return counters_;
    }
    // Counters::wait_cycles without settling the execution counts (the machine asks every quantum).
    uint64_t wait_cycles() const { return counters_.wait_cycles; }

    // Back to the loaded state (registers zero, pc 0, data reloaded, counters cleared).
    void reset();

  private:
    template <bool Checked, bool Traced> friend struct EngineLoop;
    Status dispatch(uint64_t cycle_limit, uint64_t bundle_budget, bool wait_blocked);
    Status run_engine(uint64_t cycle_limit, uint64_t bundle_budget, bool wait_blocked); // the loop of engine_ and tracing

    std::shared_ptr<const Program> prog_;
    Engine engine_;
    Tracer* tracer_ = nullptr;
    std::unique_ptr<Core> core_;
    const uint64_t* cycle_at_ = nullptr; // &core_->cycle, set with core_
    const uint32_t* pc_at_ = nullptr;    // &core_->pc
    std::unique_ptr<MemorySystem> mem_;
    // Channels are sparse 32-bit ids: every attachment by id (sorted), and for the engines one
    // slot per id the program uses (Program::channel_ids(), DecodedOp::chan).
    std::vector<std::pair<uint32_t, Channel*>> attached_;
    std::vector<Channel*> slots_;
    mutable Counters counters_;
    // Fast engine: a threaded chain counts the bundles it finishes by pass (a stretch issued in
    // address order, from the chain's head or a jump's target to a jump or the chain's stop):
    // pass_enter_[q] passes began at bundle q, pass_leave_[r + 1] ended after bundle r, so
    // bundle pc was finished sum(enter[0..pc]) - sum(leave[0..pc]) more times (flush_passes).
    mutable std::vector<uint64_t> pass_enter_, pass_leave_;
    mutable bool passes_dirty_ = false;
    void flush_passes() const;
    Status status_ = Status::Running;
    std::optional<Fault> fault_;
    uint32_t blocked_channel_ = 0;
    bool compiled_on_ = true;
    // A program without built-in runs whose runs may be compiled at run time: its entry, the
    // cycles run since they were last counted in it, and poll_runtime, which counts them and
    // switches this processor to the runs once they are ready.
    struct RuntimeCompiled* runtime_ = nullptr;
    uint64_t runtime_unreported_ = 0;
    void poll_runtime();
    std::vector<PendingWrite> landed_; // tracing: writes landed in the cycle not yet reported
};

} // namespace nesshi::iss
