// One PE's simulation: processors, FIFOs, the scheduler (see pe.hpp), the statistics.
#include "pe.hpp"

#include "iss/cache.hpp"

#include "kernels/abi.hpp"
#include "iss/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <stdexcept>

namespace nesshi::machine {

namespace abi = kernels::abi;

namespace {

constexpr std::uint64_t kSoloChunk = 4096; // cycles a stage runs alone before the host looks again

// An OS or IC processor with its input FIFO and its two output FIFOs.
struct Stage {
    std::unique_ptr<iss::Processor> proc;
    Fifo* in = nullptr;
    Fifo* out[3] = {nullptr, nullptr, nullptr}; // by channel number (1, 2)
    const char* name = "";

    // A processor whose last run only waited for words not yet sent (a bundle receiving several
    // words of a message its producer has not finished) cannot progress until its FIFOs change.
    bool starved = false;
    std::uint64_t starved_at = 0; // in->pushed() when it starved

    // For the turn rule's bounds, per pc: the words the bundle receives, and the fewest bundles
    // (each at least a cycle) before a FIFO bundle can issue, through any branch (an indirect
    // jump may lead to one at once; after a halt, never).
    std::vector<std::uint8_t> recv_need;
    std::vector<std::uint32_t> fifo_dist;
    void analyse() {
        const iss::Program& p = proc->program();
        const std::uint32_t n = p.size();
        constexpr std::uint32_t kFar = ~std::uint32_t{0};
        recv_need.assign(n, 0);
        fifo_dist.assign(n, kFar);
        std::vector<std::vector<std::uint32_t>> preds(n);
        std::vector<std::uint32_t> queue;
        for (std::uint32_t pc = 0; pc < n; ++pc) {
            const iss::DecodedBundle& b = p.bundles()[pc];
            bool falls = true, indirect = false;
            for (std::uint32_t i = 0; i < b.count; ++i) {
                const iss::DecodedOp& d = p.ops()[b.first + i];
                switch (d.instr.info().kind) {
                case isa::Kind::Recv: ++recv_need[pc]; break;
                case isa::Kind::Branch:
                    if (d.imm < n) preds[d.imm].push_back(pc);
                    break;
                case isa::Kind::Jump:
                case isa::Kind::JumpLink:
                    falls = false;
                    if (d.imm < n) preds[d.imm].push_back(pc);
                    break;
                case isa::Kind::JumpReg: indirect = true; falls = false; break;
                case isa::Kind::Halt: falls = false; break;
                default: break;
                }
            }
            if (falls && pc + 1 < n) preds[pc + 1].push_back(pc);
            if (b.fifo) fifo_dist[pc] = 0;
            else if (indirect) fifo_dist[pc] = 1;
            if (fifo_dist[pc] != kFar) queue.push_back(pc);
        }
        // Breadth first from the FIFO bundles backwards; indirect jumps (distance 1) join in order.
        std::stable_sort(queue.begin(), queue.end(), [&](std::uint32_t a, std::uint32_t b) { return fifo_dist[a] < fifo_dist[b]; });
        for (std::size_t h = 0; h < queue.size(); ++h)
            for (std::uint32_t q : preds[queue[h]])
                if (fifo_dist[q] == kFar) {
                    fifo_dist[q] = fifo_dist[queue[h]] + 1;
                    queue.push_back(q);
                }
    }

    // Model S: earliest cycle at which the processor can make progress; kNever if it cannot now.
    std::uint64_t next_event() const {
        if (starved && in->pushed() == starved_at) return kNever;
        switch (proc->status()) {
        case iss::Status::Running: return proc->cycle();
        case iss::Status::Blocked: {
            const std::uint32_t ch = proc->blocked_channel();
            if (ch == abi::kChIn) return in->empty() ? kNever : std::max(proc->cycle(), in->ready(0));
            const Fifo& o = *out[ch];
            return o.writable() >= sends_needed(ch) ? std::max(proc->cycle(), o.room_cycle) : kNever;
        }
        case iss::Status::Halted:
        case iss::Status::Faulted: break;
        }
        return kNever;
    }
    // Words the blocked bundle sends on `ch`.
    std::size_t sends_needed(std::uint32_t ch) const {
        const iss::Program& p = proc->program();
        const iss::DecodedBundle& b = p.bundles()[proc->pc()];
        std::size_t n = 0;
        for (std::uint32_t i = 0; i < b.count; ++i) {
            const iss::DecodedOp& d = p.ops()[b.first + i];
            n += d.instr.info().kind == isa::Kind::Send && d.imm == ch;
        }
        return n;
    }
    bool blocked_on_send() const {
        return proc->status() == iss::Status::Blocked && proc->blocked_channel() != abi::kChIn;
    }
    // Runs up to `horizon` (exclusive) or until it blocks; first, when it waits at a FIFO bundle,
    // waits until `earliest`, the turn rule's bound on its next action (pipelined models), or
    // the room it waits for (S).
    void run(std::uint64_t horizon, std::optional<std::uint64_t> earliest = std::nullopt) {
        if (!earliest) {
            if (blocked_on_send()) proc->idle_until(out[proc->blocked_channel()]->room_cycle);
        } else if (proc->status() == iss::Status::Blocked || recv_need[proc->pc()]) {
            proc->idle_until(*earliest);
        }
        if (horizon <= proc->cycle()) return;
        const std::uint64_t busy_before = busy();
        const iss::Status s = proc->run(horizon - proc->cycle());
        // Starved: it issued nothing though every word in its FIFO has arrived, so more time alone
        // does not help (words still in flight would: those are waited for cycle by cycle).
        starved = s == iss::Status::Running && busy() == busy_before && !in->empty() &&
                  in->all_ready(proc->cycle());
        starved_at = in->pushed();
        if (s == iss::Status::Faulted || s == iss::Status::Halted)
            throw std::runtime_error(fmt::format("{} processor stopped: {}\n{}", name, iss::status_name(s),
                                                 proc->fault_report()));
    }
    std::uint64_t busy() const { return proc->cycle() - proc->wait_cycles(); }

    // --trace-json: the bundles with FIFO operations, whose executions are communication cycles.
    std::vector<std::uint32_t> fifo_pcs;
    std::uint64_t communication() const {
        std::uint64_t n = 0;
        for (std::uint32_t pc : fifo_pcs) n += proc->counters().exec[pc];
        return n;
    }
};

// A stage's clock and its wait and communication cycles so far (the rest is processing).
struct Meter {
    std::uint64_t clock = 0, wait = 0, communication = 0;
};

// Gathers a stage's time into Activity stretches (see pe.hpp).
class ActivityLog {
  public:
    void add(const Meter& now) {
        if (now.clock <= last_.clock) return;
        if (open_.end == 0) open_.start = last_.clock;
        open_.end = now.clock;
        open_.wait += now.wait - last_.wait;
        open_.communication += now.communication - last_.communication;
        open_.processing = (open_.end - open_.start) - open_.wait - open_.communication;
        last_ = now;
        if (open_.end - open_.start >= span_) flush();
    }
    std::vector<Activity> finish() {
        flush();
        return std::move(done_);
    }

  private:
    void flush() {
        if (open_.end == 0) return;
        done_.push_back(open_);
        open_ = Activity{};
        if (done_.size() >= 8000) { // keep the trace small: merge neighbours, double the span
            std::vector<Activity> merged;
            for (std::size_t i = 0; i < done_.size(); i += 2) {
                Activity a = done_[i];
                if (i + 1 < done_.size()) {
                    const Activity& b = done_[i + 1];
                    a.end = b.end;
                    a.wait += b.wait;
                    a.communication += b.communication;
                    a.processing += b.processing;
                }
                merged.push_back(a);
            }
            done_ = std::move(merged);
            span_ *= 2;
        }
    }
    Meter last_;
    Activity open_;
    std::vector<Activity> done_;
    std::uint64_t span_ = 256; // cycles: the trace's resolution
};

constexpr std::size_t kHotBundles = 10; // the most executed bundles each stage's detail lists

StageCycles stage_cycles(const iss::Processor& p, const iss::Stats& s) {
    StageCycles c;
    c.processing = s.processing_cycles;
    c.communication = s.communication_cycles;
    c.wait = s.wait_cycles;
    c.bundles = s.bundles;
    c.ops = s.ops;
    c.processing_ops = s.processing_ops;
    c.units = p.program().machine().slots.size();
    c.words_received = s.words_received;
    c.words_sent = s.words_sent;
    return c;
}

} // namespace

class Pe {
  public:
    Pe(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt, const Options& mo,
       std::vector<std::uint32_t> corners, CornerSink sink)
        : mo_(mo), serial_(mo.model == Model::S),
          os_in_(mo.fifo_capacity, serial_ ? 0 : mo.fifo_latency), ic_in_(mo.fifo_capacity, serial_ ? 0 : mo.fifo_latency),
          sc_os_(mo.fifo_capacity, serial_ ? 0 : mo.fifo_latency), sc_ic_(mo.fifo_capacity, serial_ ? 0 : mo.fifo_latency),
          sc_(prep, opt, setup.sc_prices, std::move(corners), mo.window, mo.ray_slots, sink, sc_os_, sc_ic_, os_in_) {
        const iss::Engine engine = mo.checked ? iss::Engine::Checked : iss::Engine::Fast;
        os_.name = "OS";
        os_.proc = std::make_unique<iss::Processor>(setup.os_prog, engine);
        os_.in = &os_in_;
        os_.out[abi::kChOsIc] = &ic_in_;
        os_.out[abi::kChOsSc] = &sc_os_;
        ic_.name = "IC";
        ic_.proc = std::make_unique<iss::Processor>(setup.ic_prog, engine);
        ic_.in = &ic_in_;
        ic_.out[abi::kChIcOs] = &os_in_;
        ic_.out[abi::kChIcSc] = &sc_ic_;
        for (Stage* s : {&os_, &ic_}) {
            if (mo.traced())
                for (std::uint32_t pc = 0; pc < s->proc->program().size(); ++pc)
                    if (s->proc->program().bundles()[pc].fifo) s->fifo_pcs.push_back(pc);
            s->proc->attach_channel(abi::kChIn, s->in);
            for (std::uint32_t ch = 0; ch < std::size(s->out); ++ch) // the output channels named above
                if (s->out[ch]) s->proc->attach_channel(ch, s->out[ch]);
        }
        // The host's images: a machine whose memory cannot hold them is named with its stage.
        auto load = [](Stage& st, const char* stage, const char* what, std::uint32_t base, std::span<const std::uint8_t> bytes) {
            try {
                st.proc->memory().load_data(base, bytes);
            } catch (const iss::LoadError& e) {
                const isa::Machine& m = st.proc->program().machine();
                throw iss::LoadError(fmt::format("{} stage, machine '{}' ({}): {}: {}", stage, m.name, m.source, what,
                                                 e.message()));
            }
        };
        load(os_, "OS", "the voxel map", setup.os_image.base, setup.os_image.bytes);
        ic_.proc->attach_memory("global", setup.global);
        if (!setup.ic_resident.bytes.empty())
            load(ic_, "IC", "the scene's resident data (header, voxel lists and shapes)", setup.ic_resident.base,
                 setup.ic_resident.bytes);
        os_in_.consumer_proc = os_.proc.get();
        ic_in_.consumer_proc = ic_.proc.get();
        sc_os_.consumer_clock = sc_ic_.consumer_clock = &sc_.clock_ref();
        os_in_.producer_proc = ic_.proc.get();
        ic_in_.producer_proc = sc_os_.producer_proc = os_.proc.get();
        sc_ic_.producer_proc = ic_.proc.get();
        if (!serial_) { // stages 0 OS, 1 IC, 2 SC
            os_in_.follow_turns(&turns_, 0, 1, 2);
            ic_in_.follow_turns(&turns_, 1, 0);
            sc_os_.follow_turns(&turns_, 2, 0);
            sc_ic_.follow_turns(&turns_, 2, 1);
            sc_.follow_turns(&turns_);
            os_.analyse();
            ic_.analyse();
        }
        if (mo.cache.enabled) {
            cache_.emplace(mo.cache);
            ic_.proc->attach_cache("global", &*cache_);
        }
    }

    // Runs until every corner given so far is finished, or until the next action of every stage
    // is at or past `until` (dynamic balancing: DIS may give more corners at `until`).
    void run_until(std::uint64_t until, std::atomic<std::uint64_t>& corners_done) {
        while (!sc_.done()) {
            if (serial_) {
                std::uint64_t key[3] = {next_of(0), next_of(1), next_of(2)};
                int w = 0;
                for (int i = 1; i < 3; ++i)
                    if (key[i] < key[w]) w = i;
                if (key[w] == kNever) deadlock();
                if (std::max(key[w], now_) >= until) break;
                step_serial(w, until);
            } else if (!step_exact(until)) {
                break;
            }
            if (sc_.corners_done() != reported_) {
                corners_done += sc_.corners_done() - reported_;
                reported_ = sc_.corners_done();
            }
            if (mo_.traced()) {
                sample();
                log_activity();
            }
        }
    }

    void give(std::uint32_t corner, std::uint64_t at) { sc_.give(corner, at); }
    std::size_t room(std::size_t target) const { return sc_.room(target); }
    bool done() const { return sc_.done(); }

  private:
    std::uint64_t clock_of(int i) const { return i == 0 ? os_.proc->cycle() : i == 1 ? ic_.proc->cycle() : sc_.clock(); }
    std::uint64_t next_of(int i) const { return i == 0 ? os_.next_event() : i == 1 ? ic_.next_event() : sc_.next_event(); }

    [[noreturn]] void deadlock() const {
        auto state = [](const Stage& s) {
            if (s.proc->status() != iss::Status::Blocked)
                return fmt::format("{} at cycle {}{}", iss::status_name(s.proc->status()), s.proc->cycle(),
                                   s.starved ? ", waiting for the rest of a message" : "");
            return fmt::format("blocked on channel {} ({}) at cycle {}", s.proc->blocked_channel(),
                               s.proc->blocked_channel() == abi::kChIn ? "empty input" : "full output", s.proc->cycle());
        };
        const int safe = deadlock_free_ray_slots(mo_.fifo_capacity);
        throw std::runtime_error(fmt::format(
            "deadlock: every stage waits on another (FIFO capacity {} words)\n  OS: {}\n  IC: {}\n  SC: at cycle {}, "
            "{} corners done, {} rays in flight\n  FIFO words: OS in {}, IC in {}, SC from OS {}, SC from IC {}\n"
            "  The window ({} corners) bounds corners, not rays: each hit spawns shadow, reflection and refraction "
            "rays. A ray has one message in the FIFOs at a time, at most {} words (a VISIT), so with at most {} / {} = "
            "{} ray{} in flight no FIFO can fill: limit them with --ray-slots {} (nesshi render's default when "
            "--fifo-capacity is given without --window)",
            mo_.fifo_capacity, state(os_), state(ic_), sc_.clock(), sc_.corners_done(), sc_.rays_in_flight(),
            os_in_.size(), ic_in_.size(), sc_os_.size(), sc_ic_.size(), mo_.window, kLongestMessageWords,
            mo_.fifo_capacity, kLongestMessageWords, safe, safe == 1 ? "" : "s", safe));
    }

    void check_limit(std::uint64_t t) const {
        if (mo_.max_cycles && t > mo_.max_cycles)
            throw std::runtime_error(fmt::format("the PE passed the cycle limit ({} cycles)", mo_.max_cycles));
    }

    // The turn rule's bound on a processor's next FIFO action (turns.hpp): its cycle, or the
    // arrival of the words its bundle receives (sent ones, or what its producers can still send),
    // or the room its send waits for.
    Bound bound(int i) const {
        if (i == 2) return sc_.bound();
        const Stage& s = i == 0 ? os_ : ic_;
        Bound b;
        const iss::Status st = s.proc->status();
        if (st == iss::Status::Halted || st == iss::Status::Faulted) return b;
        const std::uint64_t cycle = s.proc->cycle();
        b.floor = cycle;
        if (st == iss::Status::Blocked && s.proc->blocked_channel() != abi::kChIn) {
            const std::uint32_t ch = s.proc->blocked_channel();
            const Fifo& o = *s.out[ch];
            const std::uint64_t known = o.room_from(cycle, s.sends_needed(ch));
            b.own = known == Fifo::kNone ? kNever : known;
            // The consumer's next receive. Constant indices: a store at a computed one kept `b` on
            // the stack, and its copy out stalled on reading it back (Pe::bound 4.8 % of mount V).
            const int consumer = &o == &ic_in_ ? 1 : &o == &os_in_ ? 0 : 2;
            b.via = {consumer == 0 ? 1 : kNever, consumer == 1 ? 1 : kNever, consumer == 2 ? 1 : kNever};
            return b;
        }
        const std::size_t need = s.recv_need[s.proc->pc()];
        if (need == 0) {
            const std::uint32_t d = s.fifo_dist[s.proc->pc()];
            b.own = d == ~std::uint32_t{0} ? cycle : cycle + d; // (a halt ahead: it runs to it)
            return b;
        }
        const std::uint64_t t = s.in->arrival(need);
        b.own = t == kNever ? kNever : std::max(cycle, t);
        if (need > s.in->size()) { // not all sent: a producer may still send some first
            b.via[i == 0 ? 1 : 0] = s.in->latency();
            if (i == 0) b.via[2] = s.in->latency();
        }
        return b;
    }
    // The stage waits for room on a full FIFO (not merely for its turn to send).
    bool wants_room(int i) const {
        if (i == 2) return sc_.wants_room();
        const Stage& s = i == 0 ? os_ : ic_;
        if (!s.blocked_on_send()) return false;
        const std::uint32_t ch = s.proc->blocked_channel();
        return s.out[ch]->room_at(s.proc->cycle()) < s.sends_needed(ch);
    }

    // Runs the stage with the earliest bound (ties: OS, IC, SC) with its turn horizon, and up to
    // `quantum` cycles past it (it blocks at its first FIFO action past the horizon; the quantum
    // only sets how often the host switches stages); never past `until` (DIS may hand out more
    // corners there). Returns false when every stage's next action is at or past `until`.
    bool step_exact(std::uint64_t until) {
        const std::array<Bound, 3> b{bound(0), bound(1), bound(2)};
        const std::array<std::uint64_t, 3> e = settle(b, -1);
        int w = 0;
        for (int i = 1; i < 3; ++i)
            if (e[i] < e[w]) w = i;
        if (e[w] == kNever) deadlock();
        if (e[w] >= until) return false;
        const std::array<std::uint64_t, 3> others = settle(b, w);
        std::uint64_t turn = kNever;
        for (int i = 0; i < 3; ++i)
            if (i != w && others[i] != kNever) turn = std::min(turn, i < w ? others[i] - 1 : others[i]);
        turns_.horizon[w] = turn;
        if (mo_.fifo_capacity != 0) // only a bounded FIFO asks (Fifo::pop); unbounded ones always have room
            for (int i = 0; i < 3; ++i) turns_.wants_room[i] = i != w && wants_room(i);
        const std::uint64_t horizon = turn == kNever ? e[w] + kSoloChunk : std::max(turn, e[w]) + mo_.effective_quantum();
        check_limit(e[w]);
        if (w == 2) sc_.run(std::min(horizon, until));
        else (w == 0 ? os_ : ic_).run(std::min(horizon, until), e[w]);
        return true;
    }

    // Model S: one processor, one clock `now_`; stage w runs until it has no work.
    void step_serial(int w, std::uint64_t until) {
        check_limit(now_);
        if (w == 2) {
            sc_.idle_until(now_);
            sc_.run(kNever);
            now_ = sc_.clock();
        } else {
            Stage& s = w == 0 ? os_ : ic_;
            s.proc->idle_until(now_);
            s.run(std::min(now_ + kSoloChunk, until));
            now_ = s.proc->cycle();
        }
    }

    void sample() {
        const std::uint64_t t = std::min({os_.proc->cycle(), ic_.proc->cycle(), sc_.clock()});
        if (t < next_sample_) return;
        Sample s;
        s.cycle = t;
        s.fifo[0] = static_cast<std::uint32_t>(os_in_.size());
        s.fifo[1] = static_cast<std::uint32_t>(ic_in_.size());
        s.fifo[2] = static_cast<std::uint32_t>(sc_os_.size());
        s.fifo[3] = static_cast<std::uint32_t>(sc_ic_.size());
        samples_.push_back(s);
        next_sample_ = t + interval_;
        if (samples_.size() >= 4000) { // keep the trace small: halve the resolution
            std::vector<Sample> kept;
            for (std::size_t i = 0; i < samples_.size(); i += 2) kept.push_back(samples_[i]);
            samples_ = std::move(kept);
            interval_ *= 2;
        }
    }

    Meter meter(int i) const {
        if (i == 2) return {sc_.clock(), sc_.cycles.wait, sc_.cycles.communication};
        const Stage& s = i == 0 ? os_ : ic_;
        return {s.proc->cycle(), s.proc->wait_cycles(), s.communication()};
    }
    void log_activity() {
        for (int i = 0; i < 3; ++i) activity_[i].add(meter(i));
    }

  public:
    PeResult finish() {
        // Every processor's clock runs to the PE's end, so processing + communication + wait = end.
        const std::uint64_t end = std::max({os_.proc->cycle(), ic_.proc->cycle(), sc_.clock()});
        os_.proc->idle_until(end);
        ic_.proc->idle_until(end);
        sc_.idle_until(end);
        PeResult r;
        if (mo_.traced()) {
            log_activity();
            for (int i = 0; i < 3; ++i) r.activity[i] = activity_[i].finish();
        }
        r.end = end;
        r.os_detail = iss::compute_stats(*os_.proc, kHotBundles);
        r.ic_detail = iss::compute_stats(*ic_.proc, kHotBundles);
        r.os = stage_cycles(*os_.proc, r.os_detail);
        r.ic = stage_cycles(*ic_.proc, r.ic_detail);
        r.sc = sc_.cycles;
        r.rays = sc_.rays;
        r.traversal = sc_.traversal;
        r.bundles = r.os.bundles + r.ic.bundles;
        r.visits = os_.out[abi::kChOsIc]->pushed() / static_cast<std::uint64_t>(abi::get("MSG_VISIT"));
        r.misses = sc_os_.pushed();
        r.hits = sc_ic_.pushed() / static_cast<std::uint64_t>(abi::get("MSG_HIT"));
        r.returns = r.visits - r.hits; // every VISIT ends in a HIT or a RETURN
        if (cache_) {
            r.cache_accesses = cache_->accesses();
            r.cache_misses = cache_->misses();
        }
        r.max_fifo = std::max({os_in_.max_size(), ic_in_.max_size(), sc_os_.max_size(), sc_ic_.max_size()});
        r.samples = std::move(samples_);
        return r;
    }

  private:
    const Options& mo_;
    bool serial_;
    Fifo os_in_, ic_in_, sc_os_, sc_ic_;
    ScStage sc_;
    Stage os_, ic_;
    std::optional<iss::SetAssocCache> cache_;
    Turns turns_;
    std::uint64_t now_ = 0;
    std::uint64_t reported_ = 0; // corners already added to the caller's count
    std::vector<Sample> samples_;
    std::uint64_t next_sample_ = 0, interval_ = 256;
    std::array<ActivityLog, 3> activity_;
};

PeRun::PeRun(const MachineSetup& setup, const rt::PreparedScene& prep, const rt::RenderOptions& opt,
             const Options& mo, std::vector<std::uint32_t> corners, CornerSink sink)
    : pe_(std::make_unique<Pe>(setup, prep, opt, mo, std::move(corners), sink)) {}
PeRun::~PeRun() = default;
PeRun::PeRun(PeRun&&) noexcept = default;
PeRun& PeRun::operator=(PeRun&&) noexcept = default;
void PeRun::run_until(std::uint64_t until, std::atomic<std::uint64_t>& corners_done) { pe_->run_until(until, corners_done); }
void PeRun::give(std::uint32_t corner, std::uint64_t at) { pe_->give(corner, at); }
std::size_t PeRun::room(std::size_t target) const { return pe_->room(target); }
bool PeRun::done() const { return pe_->done(); }
PeResult PeRun::finish() { return pe_->finish(); }

} // namespace nesshi::machine
