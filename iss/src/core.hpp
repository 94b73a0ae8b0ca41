// Engine state shared by the fast and checked engines: registers, the pending-write ring,
// and the per-bundle event flags the operation handlers raise.
#pragma once

#include "iss/channel.hpp"
#include "iss/compiled.hpp"
#include "iss/memory.hpp"
#include "iss/program.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace nesshi::iss {

// At most one bundle issues per cycle and each op writes at most one register, so the writes
// landing in one cycle are bounded by (ops per bundle) x (distinct latencies).
inline constexpr uint32_t kRingCap = isa::kMaxSlots * isa::kNumOpClasses;

struct RingWrite {
    uint16_t reg;
    uint32_t value;
    uint32_t op;
};
struct RingSlot {
    uint32_t n = 0;
    std::array<RingWrite, kRingCap> w;
};

enum Event : uint32_t { kTaken = 1, kHalt = 2, kFault = 4, kStall = 8 };

struct Core {
    std::array<uint32_t, kNumRegs + 1> r{}; // + scratch slot kNoReg
    std::array<uint64_t, kNumRegs + 1> busy{}; // checked engine: cycle the last pending write lands
    uint64_t cycle = 0;
    uint64_t land_next = 0; // next cycle whose writes have not landed yet
    uint32_t pc = 0, next_pc = 0;
    uint32_t event = 0;
    uint32_t stall = 0;     // memory stall cycles raised by this bundle
    uint32_t pending = 0;   // writes in the ring
    std::vector<RingSlot> ring;
    uint64_t mask = 0;
    // Latency-1 writes of the bundle being issued: committed at its end (they land next cycle).
    uint32_t nwb = 0;
    std::array<uint16_t, isa::kMaxSlots> wb_reg;
    std::array<uint32_t, isa::kMaxSlots> wb_val;
    std::array<uint32_t, isa::kMaxSlots> wb_op;
    // The words of the bundle being issued received from (sent into) its one channel, when it moves
    // several (DecodedOp::batch): taken at its first receive, given at its last send.
    std::array<uint32_t, isa::kMaxSlots> fifo_in, fifo_out;
    std::array<uint32_t, 2> lat1_landed{}; // per file: latency-1 writes of the bundle issued last
    bool lat1_owed = false; // that bundle's landing cycle has not been through land() yet
    // The histogram bucket of the last cycle landed (land_next - 1): whether the bundle before
    // it was owed its credit, and the ring writes per file that landed in it (when that cycle
    // is last_ring_cycle). A processor stopped at a cycle boundary has landed that cycle's
    // writes without running it; Processor::write_histogram leaves that cycle out.
    bool last_owed = false;
    uint64_t last_ring_cycle = ~uint64_t{0};
    std::array<uint32_t, 2> last_ring{};
    MemorySystem* mem = nullptr;
    Channel* const* channels = nullptr; // by DecodedOp::chan (one slot per channel the program uses)
    uint64_t* words_received = nullptr;
    uint64_t* words_sent = nullptr;
    // Threaded runs (chain.hpp): bundles the chain may still finish after the current one, and
    // what the end of a bundle updates (the pass counts, Counters::taken and write_adjust, set by
    // EngineLoop::run).
    uint64_t left = 0;
    uint64_t* enter = nullptr; // Processor::pass_enter_, pass_leave_
    uint64_t* leave = nullptr;
    uint64_t* taken = nullptr;
    std::array<uint64_t*, 2> write_adjust{};
    const DecodedBundle* bundles = nullptr;
    const DecodedOp* ops = nullptr;
    const ThreadedOp* tops = nullptr; // Program::threaded()
    const FifoNeed* needs = nullptr; // Program::fifo_needs
    uint32_t nb = 0;
    uint32_t jump_from = 0, jump_to = 0; // the chain's last step across a control bundle
    // Compiled runs on a machine with a branch penalty: the bubble cycles of the branches they
    // took since run_plain entered them, and whether the last step (jump_to) had them.
    uint64_t bubbled = 0;
    bool jump_bubbled = false;
    const CompiledRun* compiled = nullptr; // by bundle, or nullptr: the program's compiled runs
    // The first fault raised inside a bundle.
    const DecodedOp* fault_op = nullptr;
    MemError fault_mem = MemError::None;
    uint32_t fault_addr = 0;

    explicit Core(uint32_t max_latency) {
        uint64_t size = std::bit_ceil(uint64_t{max_latency} + 1);
        ring.resize(size);
        mask = size - 1;
    }

    // A result issued in cycle `now` (runs keep their cycle out of the Core, chain.hpp): latency 1
    // queued for the bundle's end, longer into the ring.
    [[gnu::always_inline]] void push_at(uint64_t now, uint16_t dst, uint32_t latency, uint32_t op, uint32_t v) {
        if (latency == 1) {
            uint32_t i = nwb++;
            wb_reg[i] = dst;
            wb_val[i] = v;
            wb_op[i] = op;
            return;
        }
        RingSlot& s = ring[(now + latency) & mask];
        s.w[s.n++] = RingWrite{dst, v, op};
        ++pending;
    }

    // The queued latency-1 writes land (the bundle ended, or faulted after issuing).
    void land_direct() {
        for (uint32_t i = 0, n = nwb; i < n; ++i) r[wb_reg[i]] = wb_val[i];
        nwb = 0;
    }

    void mem_fault(const DecodedOp& d, MemError e, uint32_t addr) {
        if (!(event & kFault)) {
            fault_op = &d;
            fault_mem = e;
            fault_addr = addr;
        }
        event |= kFault;
    }

    // Memory access with range, alignment and stall accounting, for the accesses the TLB does
    // not serve (MemorySystem::tlb_hit; the handlers inline the hit path).
    // The value loaded, or kLoadFailed (a fault was raised). A value, not an out-parameter: the
    // threaded handler that calls it then tail-calls the next one, which an addressable local
    // could prevent.
    static constexpr uint64_t kLoadFailed = uint64_t{1} << 32;
    [[gnu::noinline]] uint64_t load_checked(const DecodedOp& d, uint32_t addr, uint32_t bytes) {
        MemRegion* reg = checked_region(d, addr, bytes);
        if (!reg) return kLoadFailed;
        const uint32_t v = reg->store->read(addr - reg->desc.base, bytes);
        account(*reg, addr, bytes, false);
        return v;
    }
    [[gnu::noinline]] bool store_checked(const DecodedOp& d, uint32_t addr, uint32_t bytes, uint32_t value) {
        MemRegion* reg = checked_region(d, addr, bytes);
        if (!reg) return false;
        reg->store->write(addr - reg->desc.base, bytes, value);
        account(*reg, addr, bytes, true);
        return true;
    }
    // The region of an in-range, aligned access; nullptr (and a fault raised) otherwise.
    MemRegion* checked_region(const DecodedOp& d, uint32_t addr, uint32_t bytes) {
        MemRegion* reg = const_cast<MemRegion*>(mem->find(addr, bytes));
        if (!reg || (addr & (bytes - 1))) [[unlikely]] {
            mem_fault(d, reg ? MemError::Misaligned : MemError::OutOfRange, addr);
            return nullptr;
        }
        return reg;
    }
    // After a checked access: its stall cycles, and the page into the TLB when it may go there
    // (MemorySystem::fill_tlb decides).
    void account(const MemRegion& reg, uint32_t addr, uint32_t bytes, bool write) {
        if (reg.desc.latency || reg.cache) add_stall(reg, addr, bytes, write);
        mem->fill_tlb(reg, addr);
    }
    void add_stall(const MemRegion& reg, uint32_t addr, uint32_t bytes, bool write) {
        uint32_t extra = reg.desc.latency + (reg.cache ? reg.cache->access(addr, bytes, write) : 0);
        if (extra) {
            stall += extra;
            event |= kStall;
        }
    }
};

} // namespace nesshi::iss
