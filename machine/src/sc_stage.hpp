// The SC stage of one PE, with the distributor (DIS) and collector (COL) it talks to.
//
// SC receives MISS messages from the OS and HIT messages from the IC, shades with the same code
// as the native renderer (plan_shade / finish_shade), sends shadow, reflection and refraction
// rays to the OS, and when a pixel corner's whole ray tree is resolved combines it and sends the
// colour to COL. It is modelled, not simulated: each step costs the cycles of sc_cost.hpp.
// DIS keeps at most `window` corners of this PE in flight and sends a new eye ray (9 words,
// one per cycle on its link, no SC cycles) when one finishes. Every ray sent to the OS holds one
// of `ray_slots` slots (0: all OS_SLOTS) until its MISS or HIT; a ray waits for a free slot (SC's
// own rays first; with a limited pool DIS also tops up when a slot frees, not only when a corner
// finishes).
#pragma once

#include "fifo.hpp"
#include "sc_cost.hpp"

#include "isa/ops.hpp"
#include "machine/machine.hpp"
#include "rt/camera.hpp"
#include "rt/shading.hpp"

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

namespace nesshi::machine {

inline constexpr std::uint64_t kNever = ~std::uint64_t{0};

// The price of an operation of each class (isa::OpClass): the seq machine's latency of it
// (sc_cost.hpp: a sequential shader waits on each result). All zero until set from the machine
// (render_machine.cpp's build_setup).
struct OpPrices {
    std::array<std::uint32_t, isa::kNumOpClasses> of{};
    std::uint64_t cycles(const OpMix& m) const {
        auto price = [&](isa::OpClass c) { return std::uint64_t{of[static_cast<std::size_t>(c)]}; };
        return m.alu * price(isa::OpClass::Alu) + m.fadd * price(isa::OpClass::FAdd) + m.fmul * price(isa::OpClass::FMul) +
               m.fdiv * price(isa::OpClass::FDiv) + m.load * price(isa::OpClass::Load) +
               m.store * price(isa::OpClass::Store) + m.branch * price(isa::OpClass::Branch);
    }
};

// Where finished corners go (shared by all PEs; each corner is written by one PE only).
struct CornerSink {
    std::vector<rt::Col>* colors = nullptr;
    std::vector<std::int32_t>* ids = nullptr; // may be null
    std::vector<float>* ts = nullptr;         // may be null
    int width = 0, height = 0;                // image size; corners per row = width + 1
};

class ScStage {
  public:
    ScStage(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const OpPrices& prices, std::vector<std::uint32_t> corners,
            int window, int ray_slots, CornerSink sink, Fifo& from_os, Fifo& from_ic, Fifo& to_os);

    // Earliest cycle at which SC can act (a complete message arrived, or a send waiting for room);
    // kNever when it has nothing to do. Model S's scheduler.
    std::uint64_t next_event() const;
    // The turn rule's bound on SC's next action (turns.hpp).
    Bound bound() const;
    // SC has rays to send (and slots for them).
    bool sends_due() const { return !outgoing_.empty() && !free_slots_.empty(); }
    // ...and waits for room on a full FIFO.
    bool wants_room() const { return sends_due() && to_os_.room_at(clock_) < sc_cost::kNewRayWords; }
    // Pipelined models: act only when it has the turn (turns.hpp; stage 2).
    void follow_turns(const Turns* t) { turns_ = t; }
    // Acts while its next action starts before `horizon`.
    void run(std::uint64_t horizon);
    // Model S: the one processor is busy elsewhere until `cycle`.
    void idle_until(std::uint64_t cycle);
    // Every corner given so far is finished (DIS may still give more: dynamic balancing).
    bool done() const { return finished_ == given_; }
    // DIS hands a corner to this PE at cycle `at`; it waits in DIS until a window place is free.
    void give(std::uint32_t corner, std::uint64_t at);
    // Corners this PE can take before it holds `target` (in flight plus waiting in DIS).
    std::size_t room(std::size_t target) const {
        const std::size_t held = static_cast<std::size_t>(in_flight_) + pending_.size();
        return held < target ? target - held : 0;
    }
    int window() const { return window_; }
    std::uint64_t clock() const { return clock_; }
    const std::uint64_t& clock_ref() const { return clock_; }
    std::uint64_t corners_done() const { return finished_; }
    std::size_t rays_in_flight() const { return ray_slots_ - free_slots_.size(); }

    StageCycles cycles;  // processing, communication, wait, words, units = 1, modelled
    rt::RayStats rays;
    std::array<rt::TraceCounters, rt::kRayKinds> traversal{}; // only `rays` per kind

  private:
    struct Node {
        rt::Ray ray;
        float weight = 1;
        bool hit = false;
        rt::ShadePlan plan;
        std::vector<char> blocked;
        int reflect = -1, refract = -1; // child nodes
    };
    struct Tree {
        std::uint32_t corner = 0;
        std::vector<Node> nodes;
        int outstanding = 0; // rays sent and not yet resolved
    };
    struct SlotRec {
        int tree = -1, node = -1, light = -1; // light >= 0: a shadow ray of node's plan
    };
    struct Outgoing {
        rt::Ray ray;
        SlotRec rec;
    };

    void dis_fill(std::uint64_t at);
    void spawn(const rt::Ray& ray, SlotRec rec); // queue a ray for the OS
    void flush_sends();                     // send queued rays while slots and room allow
    void send_ray(const rt::Ray& r, std::uint32_t slot, std::uint64_t& at, bool charge);
    void on_miss(std::uint32_t tag);
    void on_hit(const std::uint32_t* w);
    void resolved(int tree);
    rt::Col combine(const Tree& t, int node);
    void charge(const OpMix& m) {
        const std::uint64_t n = std::uint64_t{m.alu} + m.fadd + m.fmul + m.fdiv + m.load + m.store + m.branch;
        cycles.ops += n;
        cycles.processing_ops += n;
        processing(prices_.cycles(m));
    }
    void processing(std::uint64_t c) {
        cycles.processing += c;
        clock_ += c;
    }
    void communication(std::uint64_t words) {
        cycles.communication += words;
        clock_ += words;
    }

    const rt::PreparedScene& prep_;
    const rt::RenderOptions& opt_;
    OpPrices prices_;
    float intensity_;
    std::deque<std::uint32_t> pending_; // given by DIS, eye ray not yet sent
    std::size_t given_ = 0, finished_ = 0;
    int window_, in_flight_ = 0;
    CornerSink sink_;
    rt::Camera camera_;
    Fifo &from_os_, &from_ic_, &to_os_;
    std::uint64_t clock_ = 0, dis_clock_ = 0;
    std::vector<Tree> trees_;
    std::vector<int> free_trees_;
    std::vector<SlotRec> slots_;
    std::vector<std::uint32_t> free_slots_;
    std::size_t ray_slots_ = 0;
    bool limited_ = false;          // ray_slots below OS_SLOTS
    bool dis_held_ = false;         // limited, and DIS has a corner and window room but no slot
    // After a message: DIS's top-up (a corner finished) and SC's sends, at the clock the handling
    // ended, done when SC has the turn there.
    bool fill_due_ = false, after_msg_ = false;
    const Turns* turns_ = nullptr;
    bool may_act(std::uint64_t cycle) const { return !turns_ || turns_->may_act(2, cycle); }
    std::deque<Outgoing> outgoing_;
};

} // namespace nesshi::machine
