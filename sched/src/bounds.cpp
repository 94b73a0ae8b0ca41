// ResMII over issue-slot subsets and register-file ports, and the RecMII of a region taken as a
// loop body (see bounds.hpp), each naming what binds.
#include "sched/bounds.hpp"

#include "sched/ddg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string_view>

namespace nesshi::sched {

namespace {

// "4" for whole numbers, else two decimals: "3.50".
std::string number(double x) { return x == std::floor(x) ? fmt::format("{:.0f}", x) : fmt::format("{:.2f}", x); }

// Bundles needed when every bundle has `ports` reads of a file and op i reads sizes[i] of them:
// Martello and Toth's bin-packing bound L2, which beats reads / ports when big readers cannot
// share a bundle (3 ports: two ops that read 2 each never issue together). For each alpha,
// ops reading more than ports - alpha share a bundle with none of those reading alpha or more;
// those reading more than half the ports share none with each other; what the ops reading alpha
// to half still read beyond the room the latter leave needs bundles of its own. `big` is how
// many ops read more than half at the alpha that binds.
int packed_bundles(const std::vector<int>& sizes, int ports, int& big) {
    int best = 0;
    big = 0;
    for (int alpha = 0; 2 * alpha <= ports; ++alpha) {
        int j1 = 0, j2 = 0, room = 0, small = 0;
        for (const int k : sizes) {
            if (k > ports - alpha) ++j1;
            else if (2 * k > ports) ++j2, room += ports - k;
            else if (k >= alpha) small += k;
        }
        const int bound = j1 + j2 + std::max(0, (small - room + ports - 1) / ports);
        if (bound > best) best = bound, big = j1 + j2;
    }
    return best;
}

} // namespace

int ResBound::ii() const { return std::max(1, static_cast<int>(std::ceil(cycles - 1e-9))); }

ResBound res_mii(const isa::Machine& m, std::span<const isa::Instr> ops, std::span<const ExtraOps> extra) {
    ResBound out;
    auto consider = [&](double value, auto&& why) {
        if (value > out.cycles) out.cycles = value, out.binds = why();
    };
    const std::size_t ns = m.slots.size();
    for (std::uint32_t mask = 1; mask < (1u << ns); ++mask) {
        auto inside = [&](isa::OpClass c) { // only slots of the subset accept c
            for (std::size_t s = 0; s < ns; ++s)
                if (m.slots[s].accepts(c) && !(mask & (1u << s))) return false;
            return true;
        };
        int count = 0;
        for (const isa::Instr& in : ops)
            if (in.info().kind != isa::Kind::Nop && inside(in.info().cls)) ++count;
        for (const ExtraOps& e : extra)
            if (inside(e.cls)) count += e.count;
        const int width = std::popcount(mask);
        consider(static_cast<double>(count) / width, [&] {
            std::string names;
            for (std::size_t s = 0; s < ns; ++s)
                if (mask & (1u << s)) names += (names.empty() ? "" : ",") + m.slots[s].name;
            return fmt::format("slots {{{}}}: {} ops / {} = {}", names, count, width,
                               number(static_cast<double>(count) / width));
        });
    }
    std::array<int, isa::kNumRegFiles> reads{}, writes{};
    std::array<std::vector<int>, isa::kNumRegFiles> op_reads; // by file: each op's reads of it
    for (const isa::Instr& in : ops) {
        std::array<int, isa::kNumRegFiles> mine{};
        for (const isa::RegOperand& o : isa::register_operands(in)) {
            ++(o.write ? writes : reads)[static_cast<int>(o.file)];
            if (!o.write) ++mine[static_cast<int>(o.file)];
        }
        for (int f = 0; f < isa::kNumRegFiles; ++f)
            if (mine[static_cast<std::size_t>(f)] > 0) op_reads[static_cast<std::size_t>(f)].push_back(mine[static_cast<std::size_t>(f)]);
    }
    for (const ExtraOps& e : extra)
        for (std::size_t f = 0; f < isa::kNumRegFiles; ++f) {
            reads[f] += e.count * e.reads[f];
            writes[f] += e.count * e.writes[f];
            if (e.reads[f] > 0) op_reads[f].insert(op_reads[f].end(), static_cast<std::size_t>(e.count), e.reads[f]);
        }
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        const isa::RegFileDesc& rf = m.regs[static_cast<std::size_t>(f)];
        const std::string_view file = isa::kRegFileNames[static_cast<std::size_t>(f)];
        for (const bool write : {false, true}) {
            const int n = (write ? writes : reads)[static_cast<std::size_t>(f)];
            const std::uint32_t ports = write ? rf.write_ports : rf.read_ports;
            const double value = static_cast<double>(n) / ports;
            consider(value, [&] {
                return fmt::format("{} {} ports {}/{} = {}", file, write ? "write" : "read", n, ports, number(value));
            });
            if (write) continue; // an op writes one register at most: its writes pack exactly
            int big = 0;
            const int packed = packed_bundles(op_reads[static_cast<std::size_t>(f)], static_cast<int>(ports), big);
            if (packed > std::ceil(value - 1e-9))
                consider(packed, [&] {
                    return fmt::format("{} read ports {}/{} packed: {} ops read more than half of them = {}", file, n,
                                       ports, big, packed);
                });
        }
    }
    return out;
}

RecBound region_rec_mii(const isa::Machine& m, std::span<const BodyOp> ops, std::uint32_t bundles) {
    // A pass lasts its bundles, then the bubble of the taken branch back.
    std::uint32_t length = bundles;
    for (const BodyOp& o : ops) length = std::max(length, o.bundle + 1);
    const int ii = static_cast<int>(length) + static_cast<int>(m.branch_penalty);
    const Ddg g = scheduled_loop_ddg(m, ops, std::max(ii, 1));
    std::vector<int> circuit = g.max_ratio_circuit();
    RecBound out;
    if (circuit.empty()) return out;
    // From the op the carried edge enters (the read of the value the previous pass left) round
    // to the op that writes it.
    const auto carried = std::find_if(circuit.begin(), circuit.end(),
                                      [&](int k) { return g.edges[static_cast<std::size_t>(k)].distance > 0; });
    if (carried != circuit.end()) std::rotate(circuit.begin(), carried + 1, circuit.end());
    const Dep& back = g.edges[static_cast<std::size_t>(circuit.back())];
    out.reg = back.kind == DepKind::True ? back.why.substr(std::string_view("true ").size()) : back.why;
    const CycleRatio ratio = g.ratio(circuit);
    out.cycles = ratio.value();
    std::string text;
    for (const int k : circuit) {
        const Dep& e = g.edges[static_cast<std::size_t>(k)];
        out.chain.push_back(static_cast<std::size_t>(e.from));
        text += fmt::format("{}{} ({})", text.empty() ? "" : " -> ", ops[static_cast<std::size_t>(e.from)].instr.info().mnemonic, e.latency);
    }
    out.binds = fmt::format("{}: {} = {} cycle{}", out.reg, text, number(ratio.latency), ratio.latency == 1 ? "" : "s");
    if (ratio.distance > 1) out.binds += fmt::format(" over {} passes", ratio.distance);
    return out;
}

} // namespace nesshi::sched
