// The Processor and its two engines (fast and checked), built from one run loop.
//
// The loop, per cycle: land the writes due this cycle, pass the FIFO gate (bundles with
// send/recv only), run the bundle's handlers (all sources are read before any write lands,
// because writes go to the pending ring), then handle the rare events a handler raised
// (taken branch, halt, memory fault or stall). The checked engine adds the dynamic rules
// around the handler calls; tracing adds observers. Both are template flags, so the fast
// engine pays nothing for them. The fast engine issues its bundles in chains of threaded
// handlers (run_plain, chain.hpp) that leave exactly the state of one turn of the loop per
// bundle.
#include "iss/processor.hpp"

#include "compiled.hpp"
#include "core.hpp"
#include "runtime_compile.hpp"

#include "isa/printer.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <span>
#include <stdexcept>
#include <utility>

namespace nesshi::iss {

std::string_view status_name(Status s) {
    switch (s) {
    case Status::Running: return "running";
    case Status::Blocked: return "blocked";
    case Status::Halted: return "halted";
    case Status::Faulted: return "faulted";
    }
    return "?";
}

namespace {

constexpr uint64_t kNoLimit = std::numeric_limits<uint64_t>::max();
// Bundles one threaded chain may issue. Without sibling-call optimisation (-O0, sanitizers)
// every handler call takes a stack frame, so the chain is kept short there.
#if defined(__OPTIMIZE__) && !defined(__SANITIZE_ADDRESS__)
constexpr uint64_t kChainCap = uint64_t{1} << 20;
#else
constexpr uint64_t kChainCap = 16;
#endif

std::string op_note(const Program& prog, const DecodedOp& d, uint64_t issued) {
    std::string src = prog.source_of(d.bundle);
    return fmt::format("{} (bundle {}, issued in cycle {}{}{})", isa::format_instr(d.instr), d.bundle, issued,
                       src.empty() ? "" : ", ", src);
}

} // namespace

// Everything the loop needs that is not in Core; a friend of Processor.
template <bool Checked, bool Traced> struct EngineLoop {
    Processor& p;
    Core& c;
    const Program& prog;
    Counters& k;
    CycleEvent::What gap_kind = CycleEvent::Bubble;

    explicit EngineLoop(Processor& proc)
        : p(proc), c(*proc.core_), prog(*proc.prog_), k(proc.counters_) {}

    Status fault(FaultKind kind, std::string msg, std::vector<std::string> notes = {}) {
        c.nwb = 0; // a faulting bundle's results are dropped
        p.fault_ = Fault{kind, c.cycle, c.pc, std::move(msg), std::move(notes)};
        return Status::Faulted;
    }

    void emit(CycleEvent::What what, uint64_t cycle) {
        CycleEvent ev{what, cycle, c.pc, &p.landed_};
        p.tracer_->on_cycle(prog, ev);
        p.landed_.clear();
    }

    // Land every write due up to and including the current cycle. Latency-1 writes were
    // committed at the end of their bundle; here they only count towards the port histogram.
    //
    // Port histogram: every issued bundle is credited, through its execution count, with one
    // cycle in bucket lat1_writes (see Processor::write_histogram); that is exactly what the
    // common case below would count, so it counts nothing. Counters::write_adjust holds only the
    // exceptions: cycles in which no bundle's writes land, and cycles whose count differs
    // because longer-latency writes land too (the credited bucket is then moved).
    [[gnu::always_inline]] void land() {
        if (!Traced && c.pending == 0 && c.land_next == c.cycle) { // the common case: nothing in the ring
            if (!c.lat1_owed) [[unlikely]] { // nothing was issued in the cycle before: nothing lands
                ++k.write_adjust[0][0];
                ++k.write_adjust[1][0];
            }
            c.last_owed = c.lat1_owed;
            c.lat1_owed = false;
            c.land_next = c.cycle + 1;
            return;
        }
        land_slow();
    }

    // The bundle issued last will not have its writes landed by land() (halt, control sent
    // outside the code): withdraw its histogram credit.
    void drop_credit() {
        if (!c.lat1_owed) return;
        --k.write_adjust[0][c.lat1_landed[0]];
        --k.write_adjust[1][c.lat1_landed[1]];
        c.lat1_owed = false;
    }

    void land_slow() {
        while (c.land_next <= c.cycle) {
            const bool owed = c.lat1_owed;
            uint32_t n[2] = {owed ? c.lat1_landed[0] : 0, owed ? c.lat1_landed[1] : 0};
            c.lat1_owed = false;
            c.last_owed = owed;
            if (!Traced && c.pending == 0) {
                if (!owed) {
                    ++k.write_adjust[0][0];
                    ++k.write_adjust[1][0];
                }
                uint64_t gap = c.cycle - c.land_next;
                if (gap) c.last_owed = false; // the last cycle landed is one of the gap's
                k.write_adjust[0][0] += gap;
                k.write_adjust[1][0] += gap;
                c.land_next = c.cycle + 1;
                return;
            }
            RingSlot& s = c.ring[c.land_next & c.mask];
            const uint32_t count = s.n;
            uint32_t ring_float = 0; // of the ring writes landing now, those to the FPRF
            for (uint32_t i = 0; i < count; ++i) {
                const RingWrite w = s.w[i];
                c.r[w.reg] = w.value;
                ring_float += (w.reg >> 7) & 1;
                if constexpr (Traced) p.landed_.push_back({w.reg, w.value, c.land_next, w.op});
            }
            c.pending -= count;
            s.n = 0;
            if (count) {
                c.last_ring_cycle = c.land_next;
                c.last_ring = {count - ring_float, ring_float};
            }
            if (count || !owed) [[unlikely]] { // else the credit is right: only latency-1 writes land
                const uint32_t ring[2] = {count - ring_float, ring_float};
                for (int f = 0; f < 2; ++f) {
                    if (owed && !ring[f]) continue;
                    if (owed) --k.write_adjust[f][n[f]];
                    ++k.write_adjust[f][n[f] + ring[f]];
                }
            }
            if constexpr (Traced)
                if (c.land_next < c.cycle) emit(gap_kind, c.land_next);
            ++c.land_next;
        }
    }

    // Fast engine: bundle c.pc and those after it in its run (DecodedBundle::run) issue here,
    // and, without a branch penalty, the runs control goes to (compiled runs: with one too,
    // across constant-target control bundles, bubbles included), until a run's last bundle, a
    // bundle whose handlers raised an event other than a taken branch, or one whose successor
    // is a FIFO bundle whose fast gate does not pass (chain.hpp) has executed its operations;
    // loop() then finishes that bundle as any other, and its fifo_gate decides at the FIFO
    // bundle. Only those stops end a chain early, so the cycle limit and the budget are checked
    // once; inside it land_next always equals the cycle and the bundle before is owed its
    // histogram credit, so landing reduces to the cycle's ring slot, and that state is written
    // back once, at the end (compiled runs also stop in a taken branch whose bubble the budget
    // has no room for). The chain of threaded handlers (chain.hpp) leaves c.pc at the bundle it
    // stops in, and c.left at the cycles it could still have run.
    [[gnu::always_inline]] void run_plain(const DecodedBundle* bundles, uint64_t limit, uint64_t& budget) {
        const uint64_t n = std::min<uint64_t>({budget, limit - c.cycle, kChainCap});
        c.left = n - 1;
        c.jump_to = ~uint32_t{0};
        c.bubbled = 0;
        c.jump_bubbled = false;
        ++c.enter[c.pc]; // a pass begins at the head...
        p.passes_dirty_ = true;
        if (c.compiled) { // compiled runs (issue 16 step 6, compiled.hpp): same contract as the chain
            detail::run_compiled(c);
        } else {
            const ThreadedOp& head = c.tops[bundles[c.pc].first];
            head.fn(c, head, c.cycle, c.left);
        }
        const uint32_t pc = c.pc;
        ++c.leave[pc]; // ...and the last one ends before the bundle the chain stops in (loop() counts it)
        const uint64_t cycles = n - 1 - c.left; // all but the one it stops in, and the bubbles
        budget -= cycles - c.bubbled;
        k.bubble_cycles += c.bubbled;
        if (!(c.event & kTaken)) c.next_pc = pc + 1; // only a control bundle sets it
        c.land_next = c.cycle + 1;
        c.lat1_owed = false;
        if (cycles) { // this cycle landed the bundle before's writes (a fault here leaves it so), or a bubble's
            const bool jumped = pc == c.jump_to;
            c.last_owed = !(jumped && c.jump_bubbled);
            c.lat1_landed = bundles[jumped ? c.jump_from : pc - 1].lat1_writes;
        }
    }

    // The bundle's latency-1 writes land at the start of the next cycle.
    void commit(const DecodedBundle& b) {
        const uint32_t count = c.nwb;
        for (uint32_t i = 0; i < count; ++i) {
            c.r[c.wb_reg[i]] = c.wb_val[i];
            if constexpr (Traced) p.landed_.push_back({c.wb_reg[i], c.wb_val[i], c.cycle + 1, c.wb_op[i]});
        }
        c.lat1_landed = b.lat1_writes;
        c.lat1_owed = true;
        c.nwb = 0;
    }

    // Writes still in flight at a halt land at once (they are not counted as port use).
    void flush() {
        for (uint64_t t = c.land_next; c.pending && t <= c.land_next + c.mask; ++t) {
            RingSlot& s = c.ring[t & c.mask];
            for (uint32_t i = 0; i < s.n; ++i) c.r[s.w[i].reg] = s.w[i].value;
            c.pending -= s.n;
            s.n = 0;
        }
        c.busy.fill(0);
    }

    void wait_until(uint64_t target) {
        if constexpr (Traced) emit(CycleEvent::Wait, c.cycle);
        uint64_t gap = target - c.cycle;
        k.wait[c.pc] += gap;
        k.wait_cycles += gap;
        c.cycle = target;
        gap_kind = CycleEvent::Wait;
    }

    enum class Gate { Go, Retry, Stop };

    // A receive that can never complete: its channel is closed and short of words.
    Gate deadlock(const DecodedOp& d, std::string msg, Status& st) {
        st = fault(FaultKind::Deadlock, std::move(msg),
                   {fmt::format("{} received {} words before", prog.format_op(d.instr), k.words_received)});
        return Gate::Stop;
    }

    // A bundle with FIFO operations issues only when every recv has a word and every send
    // has room; otherwise the whole bundle waits.
    Gate fifo_gate(const DecodedBundle& b, uint64_t limit, bool wait_blocked, Status& st) {
        const DecodedOp* ops = prog.ops().data() + b.first;
        for (uint32_t i = 0; i < b.count; ++i) {
            const DecodedOp& d = ops[i];
            isa::Kind kind = d.instr.info().kind;
            if (kind != isa::Kind::Recv && kind != isa::Kind::Send) continue;
            uint32_t ch = d.imm;
            Channel* chan = p.slots_[d.chan];
            if (!chan) {
                st = fault(FaultKind::NoChannel, fmt::format("{} uses channel {}, which is not attached",
                                                              d.instr.info().mnemonic, ch));
                return Gate::Stop;
            }
            const size_t need = d.need; // this op plus earlier ops of the bundle on the same channel and direction
            if (kind == isa::Kind::Recv) {
                if (chan->readable(c.cycle, need) >= need) continue;
                std::optional<uint64_t> ready = chan->front_ready();
                if (ready && *ready > c.cycle) { // the word exists but arrives later: wait for it
                    wait_until(std::min(*ready, limit));
                    return Gate::Retry;
                }
                if (ready) { // front ready but a later word of this bundle is not: wait a cycle
                    // ...unless the words this bundle needs will never all be there.
                    if (chan->closed()) {
                        const size_t held = chan->readable(kNoLimit, need);
                        if (held < need)
                            return deadlock(d, fmt::format("{} on channel {}, which holds {} of the {} words this "
                                                               "bundle receives from it and will never be fed",
                                                               d.instr.info().mnemonic, ch, held, need), st);
                    }
                    wait_until(std::min(c.cycle + 1, limit));
                    return Gate::Retry;
                }
                if (chan->closed())
                    return deadlock(d, fmt::format("{} on channel {}, which is empty and will never be fed",
                                                       d.instr.info().mnemonic, ch), st);
            } else if (chan->writable() >= need) {
                continue;
            }
            p.blocked_channel_ = ch;
            if (wait_blocked && limit != kNoLimit && limit > c.cycle) wait_until(limit);
            st = Status::Blocked;
            return Gate::Stop;
        }
        return Gate::Go;
    }

    // Checked engine: no source may have a write still in flight.
    bool check_reads(const DecodedBundle& b, Status& st) {
        const DecodedOp* ops = prog.ops().data() + b.first;
        for (uint32_t i = 0; i < b.count; ++i) {
            const DecodedOp& d = ops[i];
            for (uint16_t s : {d.a, d.b, d.c}) {
                if (s == kNoReg || c.busy[s] <= c.cycle) continue;
                std::vector<std::string> notes{fmt::format("reader: {}", prog.format_op(d.instr))};
                for (const PendingWrite& w : p.inflight())
                    if (w.reg == s)
                        notes.push_back(fmt::format("producer: {} writes {} in cycle {}",
                                                    op_note(prog, prog.ops()[w.op], w.lands - prog.ops()[w.op].latency),
                                                    reg_name(s), w.lands));
                st = fault(FaultKind::InflightRead,
                           fmt::format("{} reads {} in cycle {}, but its write lands in cycle {}",
                                       d.instr.info().mnemonic, reg_name(s), c.cycle, c.busy[s]),
                           std::move(notes));
                return false;
            }
        }
        return true;
    }

    // Checked engine: writes landing in one cycle fit the write ports and name distinct registers.
    bool check_writes(const DecodedBundle& b, Status& st) {
        const isa::Machine& m = prog.machine();
        const DecodedOp* ops = prog.ops().data() + b.first;
        for (uint32_t i = 0; i < b.count; ++i) {
            const DecodedOp& d = ops[i];
            if (d.dst == kNoReg) continue;
            uint64_t t = c.cycle + d.latency;
            // Everything landing in cycle t: the ring slot, plus this bundle's latency-1 writes.
            const RingSlot& slot = c.ring[t & c.mask];
            std::array<RingWrite, kRingCap + isa::kMaxSlots> buf;
            uint32_t n = 0;
            for (uint32_t j = 0; j < slot.n; ++j) buf[n++] = slot.w[j];
            if (d.latency == 1)
                for (uint32_t j = 0; j < c.nwb; ++j) buf[n++] = {c.wb_reg[j], c.wb_val[j], c.wb_op[j]};
            std::span<const RingWrite> all(buf.data(), n);
            int file = d.dst / isa::kMaxRegs;
            uint32_t same_file = 0, same_reg = 0;
            for (const RingWrite& w : all) {
                same_file += w.reg / isa::kMaxRegs == uint32_t(file);
                same_reg += w.reg == d.dst;
            }
            uint32_t ports = m.regs[file].write_ports;
            if (same_file > ports || same_reg > 1) {
                std::vector<std::string> notes;
                for (const RingWrite& w : all) {
                    if (w.reg / isa::kMaxRegs != uint32_t(file)) continue;
                    if (same_file <= ports && w.reg != d.dst) continue;
                    const DecodedOp& o = prog.ops()[w.op];
                    notes.push_back(fmt::format("{} writes {} in cycle {}", op_note(prog, o, t - o.latency),
                                                reg_name(w.reg), t));
                }
                if (same_file > ports)
                    st = fault(FaultKind::WritePorts,
                               fmt::format("{} {} writes land in cycle {}; {} has {} {} write ports", same_file,
                                           isa::kRegFileNames[file], t, m.name, ports, isa::kRegFileNames[file]),
                               std::move(notes));
                else
                    st = fault(FaultKind::DupWrite,
                               fmt::format("{} is written twice in cycle {}", reg_name(d.dst), t), std::move(notes));
                return false;
            }
            // Stalls (memory latency, a cache, FIFO waits) delay later bundles, which the static
            // checks cannot see: a later write may then land before an earlier one.
            if (c.busy[d.dst] > t) {
                std::vector<std::string> notes{fmt::format("{} writes {} in cycle {}", op_note(prog, d, c.cycle),
                                                           reg_name(d.dst), t)};
                for (const PendingWrite& w : p.inflight())
                    if (w.reg == d.dst)
                        notes.push_back(fmt::format("{} writes {} in cycle {}",
                                                    op_note(prog, prog.ops()[w.op], w.lands - prog.ops()[w.op].latency),
                                                    reg_name(w.reg), w.lands));
                st = fault(FaultKind::WriteOrder,
                           fmt::format("{} is written in cycle {}, before an earlier write to it lands in cycle {}",
                                       reg_name(d.dst), t, c.busy[d.dst]),
                           std::move(notes));
                return false;
            }
            c.busy[d.dst] = std::max(c.busy[d.dst], t);
        }
        return true;
    }

    Status memory_fault() {
        const DecodedOp& d = *c.fault_op;
        const char* what = c.fault_mem == MemError::Misaligned ? "is not aligned to" : "is outside every memory region for";
        std::vector<std::string> notes{fmt::format("{}: base {} = 0x{:08x}, offset {}", prog.format_op(d.instr),
                                                   reg_name(d.a), c.r[d.a], int32_t(d.imm))};
        for (const auto& r : p.mem_->regions())
            notes.push_back(fmt::format("region {}: 0x{:08x}..0x{:08x}", r.desc.name, r.desc.base,
                                        uint64_t{r.desc.base} + r.desc.size - 1));
        return fault(c.fault_mem == MemError::Misaligned ? FaultKind::MemAlign : FaultKind::MemRange,
                     fmt::format("{} address 0x{:08x} {} a {}-byte access", d.instr.info().mnemonic, c.fault_addr,
                                 what, d.instr.info().mem_bytes),
                     std::move(notes));
    }

    Status run(uint64_t limit, uint64_t budget, bool wait_blocked) {
        c.enter = p.pass_enter_.data();
        c.leave = p.pass_leave_.data();
        c.taken = k.taken.data();
        c.ops = prog.ops().data();
        c.tops = prog.threaded().data();
        c.nb = prog.size();
        c.write_adjust = {k.write_adjust[0].data(), k.write_adjust[1].data()};
        c.bundles = prog.bundles().data();
        c.needs = prog.fifo_needs().data();
        Status st = loop(limit, budget, wait_blocked);
        // Stop at a cycle boundary with that cycle's writes landed, so registers and inflight()
        // show the state the next bundle will read.
        if (st == Status::Running || st == Status::Blocked) land();
        return st;
    }

    Status loop(uint64_t limit, uint64_t budget, bool wait_blocked) {
        const DecodedBundle* bundles = prog.bundles().data();
        const DecodedOp* ops = prog.ops().data();
        const uint32_t nb = prog.size();
        const uint32_t penalty = prog.machine().branch_penalty;
        uint64_t* exec = k.exec.data();
        Status st = Status::Running;
        while (c.cycle < limit && budget) {
            land();
            const DecodedBundle* bp = &bundles[c.pc];
            if (bp->slow) [[unlikely]] {
                Gate g = fifo_gate(*bp, limit, wait_blocked, st);
                if (g == Gate::Stop) return st;
                if (g == Gate::Retry) continue;
            }
            if constexpr (Checked)
                if (!check_reads(*bp, st)) return st;
            c.next_pc = c.pc + 1;
            if constexpr (Checked || Traced) { // every write through the queue, so it can be inspected
                for (const DecodedOp *o = ops + bp->first, *e = o + bp->count; o != e; ++o) o->fn_buffered(c, *o);
            } else {
                run_plain(bundles, limit, budget);
                bp = &bundles[c.pc];
            }
            const DecodedBundle& b = *bp;
            if (c.event) [[unlikely]] {
                if (c.event & kFault) { // the rest of the bundle issued: its latency-1 results land now
                    c.event = 0;
                    c.stall = 0;
                    c.land_direct();
                    return memory_fault();
                }
            }
            if constexpr (Checked)
                if (!check_writes(b, st)) return st;
            if constexpr (Traced) emit(CycleEvent::Issue, c.cycle);
            commit(b);
            ++exec[c.pc];
            ++c.cycle;
            --budget;
            if (c.event) [[unlikely]] {
                uint32_t ev = c.event;
                c.event = 0;
                if (ev & kStall) {
                    k.stall[c.pc] += c.stall;
                    k.stall_cycles += c.stall;
                    c.cycle += c.stall;
                    c.stall = 0;
                    gap_kind = CycleEvent::Bubble;
                }
                if (ev & kHalt) {
                    drop_credit();
                    flush();
                    return Status::Halted;
                }
                if (ev & kTaken) {
                    ++k.taken[c.pc];
                    k.bubble_cycles += penalty;
                    c.cycle += penalty;
                    gap_kind = CycleEvent::Bubble;
                }
            }
            if (c.next_pc >= nb) [[unlikely]] {
                drop_credit();
                --c.cycle; // report at the cycle of the bundle that sent control away
                Status s = fault(FaultKind::BadPc,
                                 c.next_pc == c.pc + 1
                                     ? fmt::format("execution ran past the last bundle ({}) without halt", nb - 1)
                                     : fmt::format("control transfer to pc {}, outside the code (bundles 0..{})",
                                                   c.next_pc, nb - 1));
                ++c.cycle;
                return s;
            }
            c.pc = c.next_pc;
        }
        return st;
    }
};

Processor::Processor(std::shared_ptr<const Program> prog, Engine engine)
    : prog_(std::move(prog)), engine_(engine) {
    reset();
}

Processor::~Processor() = default;

void Processor::reset() {
    const isa::Machine& m = prog_->machine();
    uint32_t max_lat = 1;
    for (const DecodedOp& d : prog_->ops()) max_lat = std::max(max_lat, d.latency);
    core_ = std::make_unique<Core>(max_lat);
    cycle_at_ = &core_->cycle;
    pc_at_ = &core_->pc;
    auto old = std::move(mem_);
    mem_ = std::make_unique<MemorySystem>(m);
    for (const auto& sec : prog_->object().data) mem_->load_data(sec.address, sec.bytes);
    if (old) // keep host-attached storage and caches
        for (size_t i = 0; i < old->regions().size(); ++i) {
            if (old->regions()[i].store.use_count() > 1) mem_->regions()[i].store = old->regions()[i].store;
            mem_->regions()[i].cache = old->regions()[i].cache;
        }
    slots_.resize(prog_->channel_ids().size(), nullptr); // attachments survive a reset
    core_->mem = mem_.get();
    core_->channels = slots_.data();
    core_->words_received = &counters_.words_received;
    core_->words_sent = &counters_.words_sent;
    set_compiled_runs(compiled_on_);
    counters_ = Counters{};
    size_t n = prog_->size();
    counters_.exec.assign(n, 0);
    pass_enter_.assign(n, 0);
    pass_leave_.assign(n + 1, 0);
    passes_dirty_ = false;
    counters_.wait.assign(n, 0);
    counters_.taken.assign(n, 0);
    counters_.stall.assign(n, 0);
    for (auto& h : counters_.write_adjust) h.assign(kRingCap + 1, 0);
    status_ = Status::Running;
    fault_.reset();
}

void Processor::set_engine(Engine e) {
    engine_ = e;
    // The checked engine's in-flight map is rebuilt from the ring, so engines can be switched.
    core_->busy.fill(0);
    for (const PendingWrite& w : inflight()) core_->busy[w.reg] = std::max(core_->busy[w.reg], w.lands);
}

void Processor::set_compiled_runs(bool on) {
    compiled_on_ = on;
    core_->compiled = on && prog_->compiled() ? prog_->compiled()->entry : nullptr;
    runtime_ = on && !core_->compiled ? prog_->runtime_compiled() : nullptr;
    runtime_unreported_ = 0;
}

void Processor::poll_runtime() {
    const uint64_t cycles = std::exchange(runtime_unreported_, 0);
    if (const CompiledProgram* t = detail::runtime_ran(*runtime_, *prog_, cycles)) {
        core_->compiled = t->entry;
        runtime_ = nullptr;
    }
}

bool Processor::compiled_runs() const { return core_->compiled != nullptr; }

void Processor::attach_channel(uint32_t id, Channel* ch) {
    auto at = std::lower_bound(attached_.begin(), attached_.end(), id, [](const auto& e, uint32_t k) { return e.first < k; });
    if (at != attached_.end() && at->first == id) at->second = ch;
    else attached_.insert(at, {id, ch});
    const std::vector<uint32_t>& ids = prog_->channel_ids();
    auto used = std::lower_bound(ids.begin(), ids.end(), id);
    if (used != ids.end() && *used == id) slots_[size_t(used - ids.begin())] = ch;
}

Channel* Processor::channel(uint32_t id) const {
    auto at = std::lower_bound(attached_.begin(), attached_.end(), id, [](const auto& e, uint32_t k) { return e.first < k; });
    return at != attached_.end() && at->first == id ? at->second : nullptr;
}

void Processor::attach_memory(std::string_view region, std::shared_ptr<PagedMemory> store) {
    MemRegion* r = mem_->region(region);
    if (!r) throw std::invalid_argument(fmt::format("machine {} has no memory region '{}'", prog_->machine().name, region));
    if (!store || store->size() != r->desc.size)
        throw std::invalid_argument(fmt::format("memory for region '{}' must be {} bytes", region, r->desc.size));
    r->store = std::move(store);
    for (const auto& sec : prog_->object().data)
        if (!sec.bytes.empty() && r->desc.contains(sec.address, uint32_t(sec.bytes.size())))
            r->store->write_bytes(sec.address - r->desc.base, sec.bytes);
}

void Processor::attach_cache(std::string_view region, CacheModel* cache) {
    MemRegion* r = mem_->region(region);
    if (!r) throw std::invalid_argument(fmt::format("machine {} has no memory region '{}'", prog_->machine().name, region));
    r->cache = cache;
}

Status Processor::run_engine(uint64_t limit, uint64_t budget, bool wait_blocked) {
    const bool checked = engine_ == Engine::Checked;
    if (tracer_) {
        if (checked) return EngineLoop<true, true>(*this).run(limit, budget, wait_blocked);
        return EngineLoop<false, true>(*this).run(limit, budget, wait_blocked);
    }
    if (checked) return EngineLoop<true, false>(*this).run(limit, budget, wait_blocked);
    return EngineLoop<false, false>(*this).run(limit, budget, wait_blocked);
}

Status Processor::dispatch(uint64_t limit, uint64_t budget, bool wait_blocked) {
    if (status_ == Status::Halted || status_ == Status::Faulted) return status_;
    if (!runtime_) return status_ = run_engine(limit, budget, wait_blocked);
    // A program whose runs may be compiled at run time reports the cycles it runs, a long call in
    // slices, and switches to its runs between two slices or calls once they are ready. Only a
    // call that returns when blocked and is not traced is sliced: one that waits (run_until) idles
    // to its limit once blocked, where a slice would return early or ask its channels again, and
    // a trace would show a wait cut at a slice's end as two.
    constexpr uint64_t kSlice = uint64_t{1} << 20; // about 10 ms on the interpreter
    if (core_->cycle == 0) poll_runtime(); // loaded by another processor, or compiled now under `wait`
    const bool sliced = budget == kNoLimit && !wait_blocked && !tracer_;
    for (;;) {
        const uint64_t start = core_->cycle;
        // (a bundle's bubble or stall may carry a slice past its end, even past the limit)
        const uint64_t end = runtime_ && sliced && limit > start && limit - start > kSlice ? start + kSlice : limit;
        status_ = run_engine(end, budget, wait_blocked);
        if (runtime_) {
            runtime_unreported_ += core_->cycle - start;
            if (runtime_unreported_ >= kSlice) poll_runtime();
        }
        if (status_ != Status::Running || core_->cycle < end || core_->cycle >= limit) return status_;
    }
}

Status Processor::run_until(uint64_t cycle) { return dispatch(cycle, kNoLimit, true); }

Status Processor::run(uint64_t max_cycles) {
    uint64_t limit = max_cycles > kNoLimit - core_->cycle ? kNoLimit : core_->cycle + max_cycles;
    return dispatch(limit, kNoLimit, false);
}

void Processor::idle_until(uint64_t target) {
    if (target <= core_->cycle) return;
    const uint64_t gap = target - core_->cycle;
    counters_.wait[core_->pc] += gap;
    counters_.wait_cycles += gap;
    core_->cycle = target;
}

Status Processor::step(uint64_t bundles, uint64_t max_cycles) {
    const uint64_t limit = max_cycles > kNoLimit - core_->cycle ? kNoLimit : core_->cycle + max_cycles;
    return dispatch(limit, bundles, false);
}

std::string Processor::fault_report() const { return fault_ ? format_fault(*prog_, *fault_) : std::string(); }
uint32_t Processor::reg(uint16_t flat) const { return flat < kNumRegs ? core_->r[flat] : 0; }
void Processor::set_reg(uint16_t flat, uint32_t value) {
    if (flat < kNumRegs) core_->r[flat] = value;
}

void Processor::flush_passes() const {
    uint64_t open = 0; // passes that cover pc (modulo 2^64, as the counts)
    for (size_t pc = 0; pc < pass_enter_.size(); ++pc) {
        open += pass_enter_[pc] - pass_leave_[pc];
        counters_.exec[pc] += open;
        pass_enter_[pc] = pass_leave_[pc] = 0;
    }
    pass_leave_.back() = 0; // every pass ended by the last bundle
    passes_dirty_ = false;
}

std::vector<uint64_t> Processor::write_histogram(int file) const {
    if (passes_dirty_) flush_passes();
    std::vector<uint64_t> h = counters_.write_adjust[file];
    const auto& bundles = prog_->bundles();
    for (size_t pc = 0; pc < bundles.size(); ++pc) h[bundles[pc].lat1_writes[file]] += counters_.exec[pc];
    // Stopped at a cycle boundary (cycle limit, block, a fault before the bundle issued): the
    // writes of cycle() have landed but the cycle has not run; the histogram covers cycles
    // 0 .. cycle()-1, as the cycle count does.
    const Core& c = *core_;
    if (c.land_next == c.cycle + 1) {
        const uint32_t n = (c.last_owed ? c.lat1_landed[file] : 0) + (c.last_ring_cycle == c.cycle ? c.last_ring[file] : 0);
        --h[n];
    }
    return h;
}

std::vector<PendingWrite> Processor::inflight() const {
    std::vector<PendingWrite> out;
    const Core& c = *core_;
    for (uint64_t t = c.land_next; out.size() < c.pending && t <= c.land_next + c.mask; ++t) {
        const RingSlot& s = c.ring[t & c.mask];
        for (uint32_t i = 0; i < s.n; ++i) out.push_back({s.w[i].reg, s.w[i].value, t, s.w[i].op});
    }
    return out;
}

} // namespace nesshi::iss
