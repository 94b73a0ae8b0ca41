// The SC stage: shading of HIT and MISS messages, the ray trees of pixel corners, DIS and COL.
#include "sc_stage.hpp"

#include "kbuild/ray_tag.hpp"

#include "kernels/abi.hpp"
#include "kernels/messages.hpp"

#include <algorithm>
#include <numeric>

namespace nesshi::machine {

namespace abi = kernels::abi;
using namespace sc_cost;

ScStage::ScStage(const rt::PreparedScene& prep, const rt::RenderOptions& opt, const OpPrices& prices,
                 std::vector<std::uint32_t> corners, int window, int ray_slots, CornerSink sink, Fifo& from_os,
                 Fifo& from_ic, Fifo& to_os)
    : prep_(prep), opt_(opt), prices_(prices), intensity_(rt::light_intensity(prep.scene.lights.size())),
      pending_(corners.begin(), corners.end()), given_(corners.size()), window_(std::max(1, window)), sink_(sink),
      camera_(prep.scene.view, sink.width, sink.height), from_os_(from_os),
      from_ic_(from_ic), to_os_(to_os) {
    cycles.units = 1;
    cycles.modelled = true;
    ray_slots_ = ray_slots > 0 ? std::min<std::size_t>(static_cast<std::size_t>(ray_slots), abi::kOsSlots) : abi::kOsSlots;
    limited_ = ray_slots_ < abi::kOsSlots;
    slots_.resize(ray_slots_);
    free_slots_.resize(ray_slots_);
    // Lowest slot first, so runs are easy to read in traces.
    std::iota(free_slots_.rbegin(), free_slots_.rend(), 0u);
    dis_fill(0);
}

// DIS: one eye ray per free window place, each 9 words on the DIS -> OS link.
void ScStage::dis_fill(std::uint64_t at) {
    dis_clock_ = std::max(dis_clock_, at);
    while (in_flight_ < window_ && !pending_.empty() && !free_slots_.empty() &&
           to_os_.room_at(dis_clock_) >= sc_cost::kNewRayWords) {
        const std::uint32_t corner = pending_.front();
        pending_.pop_front();
        const int cw = sink_.width + 1;
        const rt::Ray r = camera_.eye_ray(static_cast<int>(corner % static_cast<std::uint32_t>(cw)),
                                   static_cast<int>(corner / static_cast<std::uint32_t>(cw)));
        int t;
        if (!free_trees_.empty()) {
            t = free_trees_.back();
            free_trees_.pop_back();
        } else {
            t = static_cast<int>(trees_.size());
            trees_.emplace_back();
        }
        Tree& tree = trees_[static_cast<std::size_t>(t)];
        tree.corner = corner;
        tree.nodes.clear();
        tree.nodes.push_back(Node{r, 1.0f, false, {}, {}, -1, -1});
        tree.outstanding = 1;
        ++in_flight_;
        ++rays.eye_rays;
        ++traversal[static_cast<std::size_t>(rt::RayKind::eye)].rays;
        const std::uint32_t slot = free_slots_.back();
        free_slots_.pop_back();
        slots_[slot] = SlotRec{t, 0, -1};
        send_ray(r, slot, dis_clock_, false);
    }
    dis_held_ = limited_ && free_slots_.empty() && in_flight_ < window_ && !pending_.empty();
}

void ScStage::give(std::uint32_t corner, std::uint64_t at) {
    pending_.push_back(corner);
    ++given_;
    dis_fill(at);
}

void ScStage::send_ray(const rt::Ray& r, std::uint32_t slot, std::uint64_t& at, bool charge_sc) {
    const abi::Tag tag{slot, kbuild::tag_kind(r.kind), static_cast<std::uint32_t>(r.depth)};
    const abi::NewRay nr{tag.word(), {r.o.x, r.o.y, r.o.z}, {r.d.x, r.d.y, r.d.z}, r.tmin, r.tmax};
    const auto words = nr.words();
    to_os_.send(words, at, !charge_sc); // DIS's link runs ahead of SC's clock
    at += words.size();
    if (charge_sc) {
        cycles.communication += kNewRayWords;
        cycles.words_sent += kNewRayWords;
    }
}

void ScStage::spawn(const rt::Ray& ray, SlotRec rec) {
    ++traversal[static_cast<std::size_t>(ray.kind)].rays;
    ++trees_[static_cast<std::size_t>(rec.tree)].outstanding;
    outgoing_.push_back({ray, rec});
}

void ScStage::flush_sends() {
    while (!outgoing_.empty() && !free_slots_.empty() && to_os_.room_at(clock_) >= kNewRayWords) {
        const Outgoing o = outgoing_.front();
        outgoing_.pop_front();
        const std::uint32_t slot = free_slots_.back();
        free_slots_.pop_back();
        slots_[slot] = o.rec;
        send_ray(o.ray, slot, clock_, true);
    }
}

std::uint64_t ScStage::next_event() const {
    if (!outgoing_.empty() && !free_slots_.empty()) // a send waits for room in the OS's FIFO
        return to_os_.room_at(clock_) >= kNewRayWords ? std::max(clock_, to_os_.room_cycle) : kNever;
    std::uint64_t t = kNever;
    if (!from_os_.empty()) t = from_os_.ready(0);
    if (from_ic_.size() >= static_cast<std::size_t>(abi::get("MSG_HIT"))) t = std::min(t, from_ic_.ready(abi::get("MSG_HIT") - 1));
    return t == kNever ? t : std::max(t, clock_);
}

void ScStage::idle_until(std::uint64_t cycle) {
    if (cycle <= clock_) return;
    cycles.wait += cycle - clock_;
    clock_ = cycle;
}

Bound ScStage::bound() const {
    Bound b;
    b.floor = clock_;
    if (fill_due_ || after_msg_) {
        b.own = clock_;
    } else if (sends_due()) { // room from receives so far, or from the OS's next
        const std::uint64_t known = to_os_.room_from(clock_, kNewRayWords);
        b.own = known == Fifo::kNone ? kNever : known;
        b.via[0] = 1;
    } else { // the next complete message: one already sent, or one the OS or the IC may still send
        const std::uint64_t t = std::min(from_os_.arrival(1), from_ic_.arrival(static_cast<std::size_t>(abi::get("MSG_HIT"))));
        b.own = t == kNever ? kNever : std::max(clock_, t);
        b.via[0] = from_os_.latency();
        b.via[1] = from_ic_.latency();
    }
    return b;
}

void ScStage::run(std::uint64_t horizon) {
    const std::size_t hit_words = static_cast<std::size_t>(abi::get("MSG_HIT"));
    for (;;) {
        if (fill_due_ || after_msg_) { // what handling a message leads to, in the order it did
            if (turns_ && (clock_ >= horizon || !may_act(clock_))) return;
            if (fill_due_) dis_fill(clock_);
            fill_due_ = after_msg_ = false;
            flush_sends();
            if (dis_held_ && !free_slots_.empty()) dis_fill(clock_);
            continue;
        }
        if (!outgoing_.empty() && !free_slots_.empty()) {
            std::uint64_t t = kNever;
            if (turns_) { // exact: the first cycle with room, from the receives so far
                const std::uint64_t known = to_os_.room_from(clock_, kNewRayWords);
                t = known == Fifo::kNone ? kNever : known;
                if (t >= horizon || !may_act(t)) return;
            } else {
                if (to_os_.room_at(clock_) < kNewRayWords) return; // held on a full FIFO
                t = to_os_.room_cycle;
            }
            idle_until(t);
            flush_sends();
            continue;
        }
        const bool os_msg = !from_os_.empty();
        const bool ic_msg = from_ic_.size() >= hit_words;
        if (!os_msg && !ic_msg) return;
        const std::uint64_t os_ready = os_msg ? from_os_.ready(0) : kNever;
        const std::uint64_t ic_ready = ic_msg ? from_ic_.ready(hit_words - 1) : kNever;
        const bool take_os = os_ready <= ic_ready;
        const std::uint64_t start = std::max(clock_, take_os ? os_ready : ic_ready);
        if (start >= horizon || !may_act(start)) return;
        idle_until(start);
        if (take_os) {
            const std::uint32_t tag = from_os_.pop();
            communication(1);
            cycles.words_received += 1;
            on_miss(tag);
        } else {
            std::uint32_t w[6];
            from_ic_.pop_n(w, hit_words);
            communication(hit_words);
            cycles.words_received += hit_words;
            on_hit(w);
        }
        after_msg_ = true;
    }
}

void ScStage::on_miss(std::uint32_t tag) {
    charge(kDispatch);
    const std::uint32_t slot = tag & 0xffffu;
    const SlotRec rec = slots_[slot];
    free_slots_.push_back(slot);
    if (rec.light >= 0) {
        charge(kShadowFate); // the light is visible: blocked[k] stays 0
    } else {
        charge(kBackground);
        trees_[static_cast<std::size_t>(rec.tree)].nodes[static_cast<std::size_t>(rec.node)].hit = false;
        if (rec.node == 0) {
            const std::size_t corner = trees_[static_cast<std::size_t>(rec.tree)].corner;
            if (sink_.ids) (*sink_.ids)[corner] = -1;
            if (sink_.ts) (*sink_.ts)[corner] = -1.0f;
        }
    }
    resolved(rec.tree);
}

void ScStage::on_hit(const std::uint32_t* w) {
    charge(kDispatch);
    const abi::HitMsg m = abi::HitMsg::from(w);
    const std::uint32_t slot = m.tag & 0xffffu;
    const SlotRec rec = slots_[slot];
    free_slots_.push_back(slot);
    Tree& tree = trees_[static_cast<std::size_t>(rec.tree)];
    if (rec.light >= 0) {
        charge(kShadowFate);
        tree.nodes[static_cast<std::size_t>(rec.node)].blocked[static_cast<std::size_t>(rec.light)] = 1;
        ++rays.shadow_rays_blocked;
        resolved(rec.tree);
        return;
    }
    const rt::Shape& shape = prep_.shapes.shapes[m.shape];
    rt::Hit h;
    h.hit = true;
    h.t = m.t;
    h.shape = static_cast<std::int32_t>(m.shape);
    h.entity = shape.entity;
    h.a = m.u;
    h.b = m.v;
    h.front = m.front != 0;
    Node& n = tree.nodes[static_cast<std::size_t>(rec.node)];
    if (n.ray.kind == rt::RayKind::eye) {
        ++rays.eye_rays_hit;
        if (sink_.ids) (*sink_.ids)[tree.corner] = h.entity;
        if (sink_.ts) (*sink_.ts)[tree.corner] = h.t;
    } else {
        ++rays.secondary_rays_hit;
    }
    n.hit = true;
    n.plan = rt::plan_shade(prep_, opt_, intensity_, n.ray, h, n.weight, rays);
    n.blocked.assign(n.plan.lights.size(), 0);
    // The cost of what plan_shade did.
    const bool smooth = prep_.shapes.shade[m.shape].smooth;
    charge(kSurface);
    charge(shape.kind() == kernels::kShapeTriangle ? (smooth ? kPatchNormal + kNormalize : kFlatNormal)
                                          : kQuadricNormal + kNormalize);
    charge(kFaceAmbient);
    if (n.plan.ks > 0.0f) charge(kMirror);
    charge(OpMix{.branch = 1}); // per-light loop exit
    for (std::size_t k = 0; k < prep_.scene.lights.size(); ++k) charge(kLight);
    for (const rt::LightTerm& t : n.plan.lights)
        if (t.has_spec) charge(kSpecular);
    if (n.plan.reflect) charge(kReflection);
    if (n.plan.kt > 0.0f && n.ray.depth < opt_.max_depth) charge(kRefraction);
    // Spawn: shadow rays in light order, then reflection, then refraction. Copies first: adding
    // child nodes may move the node.
    const std::vector<rt::LightTerm> lights = n.plan.lights;
    const bool reflect = n.plan.reflect, refract = n.plan.refract;
    const rt::Ray reflect_ray = n.plan.reflect_ray, refract_ray = n.plan.refract_ray;
    const float reflect_weight = n.plan.reflect_weight, refract_weight = n.plan.refract_weight;
    for (std::size_t k = 0; k < lights.size(); ++k) spawn(lights[k].shadow, SlotRec{rec.tree, rec.node, static_cast<int>(k)});
    auto child = [&](const rt::Ray& r, float weight, bool is_reflect) {
        const int c = static_cast<int>(tree.nodes.size());
        Node& parent = tree.nodes[static_cast<std::size_t>(rec.node)];
        (is_reflect ? parent.reflect : parent.refract) = c;
        tree.nodes.push_back(Node{r, weight, false, {}, {}, -1, -1});
        spawn(r, SlotRec{rec.tree, c, -1});
    };
    if (reflect) child(reflect_ray, reflect_weight, true);
    if (refract) child(refract_ray, refract_weight, false);
    resolved(rec.tree);
}

// One ray of the tree resolved; when none is left the corner is done.
void ScStage::resolved(int t) {
    Tree& tree = trees_[static_cast<std::size_t>(t)];
    if (--tree.outstanding > 0) return;
    for (const Node& n : tree.nodes) {
        charge(kCombinePerRay);
        for (std::size_t k = 0; k < n.plan.lights.size(); ++k) charge(kCombinePerLight);
    }
    (*sink_.colors)[tree.corner] = combine(tree, 0);
    communication(kColWords);
    cycles.words_sent += kColWords;
    free_trees_.push_back(t);
    --in_flight_;
    ++finished_;
    fill_due_ = true;
}

rt::Col ScStage::combine(const Tree& t, int node) {
    const Node& n = t.nodes[static_cast<std::size_t>(node)];
    if (!n.hit) return rt::to_col(prep_.scene.background);
    const rt::Col refl = n.reflect >= 0 ? combine(t, n.reflect) : rt::Col{};
    const rt::Col refr = n.refract >= 0 ? combine(t, n.refract) : rt::Col{};
    return rt::finish_shade(n.plan, n.blocked, refl, refr);
}

} // namespace nesshi::machine
