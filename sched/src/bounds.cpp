// ResMII over issue-slot subsets and register-file ports, and the RecMII of a region taken as a
// loop body (see bounds.hpp), each naming what binds.
#include "sched/bounds.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

namespace nesshi::sched {

namespace {

// "4" for whole numbers, else two decimals: "3.50".
std::string number(double x) { return x == std::floor(x) ? fmt::format("{:.0f}", x) : fmt::format("{:.2f}", x); }

std::string flat_reg_name(int flat) { return fmt::format("{}{}", flat < isa::kMaxRegs ? 'r' : 'f', flat % isa::kMaxRegs); }

// Register reads and the write of one op as flat indices (r0..r127: 0..127, f0..f127: 128..255).
void regs_of(const isa::Instr& in, std::vector<int>& reads, int& write) {
    reads.clear();
    write = -1;
    for (const isa::RegOperand& r : isa::register_operands(in)) {
        const int flat = static_cast<int>(r.file) * isa::kMaxRegs + r.reg;
        if (r.write) write = flat;
        else reads.push_back(flat);
    }
}

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

RecBound region_rec_mii(const isa::Machine& m, std::span<const BodyOp> ops) {
    const std::size_t n = ops.size();
    std::vector<std::vector<int>> reads(n);
    std::vector<int> write(n), lat(n);
    for (std::size_t i = 0; i < n; ++i) {
        regs_of(ops[i].instr, reads[i], write[i]);
        lat[i] = static_cast<int>(m.latency_of(ops[i].instr.info()));
    }
    std::map<int, std::size_t> last_writer;
    for (std::size_t i = 0; i < n; ++i)
        if (write[i] >= 0) last_writer[write[i]] = i;
    RecBound out;
    for (std::size_t s = 0; s < n; ++s) {
        for (int reg : reads[s]) {
            // a live-in read: no earlier bundle writes reg
            bool live_in = true;
            for (std::size_t i = 0; i < n && ops[i].bundle < ops[s].bundle; ++i)
                if (write[i] == reg) live_in = false;
            if (!live_in || !last_writer.count(reg)) continue;
            // longest path from op s (the value read at its issue) along the registers it feeds
            std::vector<double> dist(n, -1);
            std::vector<std::size_t> from(n, n); // the producer each op's longest path comes through
            dist[s] = 0;
            struct Value {
                double ready;
                std::size_t producer;
            };
            std::map<int, Value> val;
            for (std::size_t i = s; i < n; ++i) {
                if (i != s) {
                    double d = -1;
                    for (int x : reads[i]) {
                        auto it = val.find(x);
                        if (it != val.end() && it->second.ready > d) d = it->second.ready, from[i] = it->second.producer;
                    }
                    dist[i] = d;
                }
                if (dist[i] >= 0 && write[i] >= 0) val[write[i]] = {dist[i] + lat[i], i};
                else if (write[i] >= 0) val.erase(write[i]);
            }
            auto it = val.find(reg);
            if (it == val.end() || it->second.producer != last_writer[reg] || !(it->second.ready > out.cycles)) continue;
            out.cycles = it->second.ready;
            out.reg = flat_reg_name(reg);
            out.chain.clear();
            for (std::size_t i = it->second.producer; i != n; i = i == s ? n : from[i]) out.chain.push_back(i);
            std::reverse(out.chain.begin(), out.chain.end());
            std::string text;
            for (std::size_t i : out.chain)
                text += fmt::format("{}{} ({})", text.empty() ? "" : " -> ", ops[i].instr.info().mnemonic, lat[i]);
            out.binds = fmt::format("{}: {} = {} cycle{}", out.reg, text, number(out.cycles), out.cycles == 1 ? "" : "s");
        }
    }
    return out;
}

} // namespace nesshi::sched
