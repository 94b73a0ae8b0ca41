// Differential runs of two programs on the same random data.
#include "iss/differential.hpp"

#include "iss/channel.hpp"
#include "iss/processor.hpp"
#include "iss/program.hpp"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <map>
#include <memory>
#include <random>
#include <set>

namespace nesshi::iss {

namespace {

std::string show(std::uint32_t w) { return fmt::format("{} (0x{:08x})", std::bit_cast<float>(w), w); }

// The data sections of both objects as word ranges [begin, end).
std::set<std::pair<std::uint32_t, std::uint32_t>> data_ranges(const isa::ObjectFile& a, const isa::ObjectFile& b) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> r;
    for (const isa::ObjectFile* o : {&a, &b})
        for (const isa::DataSection& s : o->data)
            r.insert({s.address & ~3u, static_cast<std::uint32_t>((s.address + s.bytes.size() + 3) & ~std::size_t{3})});
    return r;
}

// The FIFO channels either program uses, each with whether one receives from it.
std::map<std::uint32_t, bool> channels(const isa::ObjectFile& a, const isa::ObjectFile& b) {
    std::map<std::uint32_t, bool> out;
    for (const isa::ObjectFile* o : {&a, &b})
        for (const std::vector<isa::Instr>& bundle : isa::decode_bundles(*o))
            for (const isa::Instr& in : bundle)
                if (const isa::Kind k = in.info().kind; k == isa::Kind::Recv || k == isa::Kind::Send)
                    out[in.imm] = out[in.imm] || k == isa::Kind::Recv;
    return out;
}

} // namespace

std::optional<std::string> run_differential(const isa::ObjectFile& a, const isa::ObjectFile& b, const isa::Machine& m,
                                            const DiffOptions& opts, std::vector<std::uint32_t>* observed) {
    const auto ranges = data_ranges(a, b);
    Processor pa(load_program(a, m)), pb(load_program(b, m));
    if (opts.randomize_data) {
        std::mt19937_64 rng(opts.seed);
        std::uniform_real_distribution<float> u(-8.0f, 8.0f);
        for (auto [lo, hi] : ranges)
            for (std::uint32_t addr = lo; addr < hi; addr += 4) {
                const std::uint32_t w = std::bit_cast<std::uint32_t>(u(rng));
                pa.memory().poke(addr, 4, w);
                pb.memory().poke(addr, 4, w);
            }
    }
    // Each channel: the same random words in, closed (a receive past them is a deadlock, not a
    // wait), and what each program sends compared word by word.
    const std::map<std::uint32_t, bool> used = channels(a, b);
    std::vector<std::array<std::unique_ptr<QueueChannel>, 2>> queues;
    {
        std::mt19937_64 rng(opts.seed ^ 0x5eed'f1f0ULL);
        std::uniform_real_distribution<float> u(-8.0f, 8.0f);
        for (const auto& [ch, received] : used) {
            auto& q = queues.emplace_back();
            for (auto& side : q) side = std::make_unique<QueueChannel>();
            for (std::size_t k = 0; received && k < opts.fifo_words; ++k) {
                const std::uint32_t w = std::bit_cast<std::uint32_t>(u(rng));
                q[0]->feed(w);
                q[1]->feed(w);
            }
            for (auto& side : q) side->close();
            pa.attach_channel(ch, q[0].get());
            pb.attach_channel(ch, q[1].get());
        }
    }
    const char* names[2] = {"sequential", "pipelined"};
    Processor* ps[2] = {&pa, &pb};
    for (int k = 0; k < 2; ++k) {
        const Status s = ps[k]->run(opts.max_cycles);
        if (ps[k]->fault()) return fmt::format("the {} version faults:\n{}", names[k], ps[k]->fault_report());
        if (s != Status::Halted) return fmt::format("the {} version did not halt within {} cycles", names[k], opts.max_cycles);
    }
    if (observed) {
        observed->clear();
        for (const std::string& r : opts.observe) {
            const auto f = r[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float;
            observed->push_back(pa.reg(flat_reg(f, static_cast<std::uint32_t>(std::stoul(r.substr(1))))));
        }
    }
    for (auto [lo, hi] : ranges)
        for (std::uint32_t addr = lo; addr < hi; addr += 4) {
            std::uint32_t x = 0, y = 0;
            const bool okx = pa.memory().peek(addr, 4, x), oky = pb.memory().peek(addr, 4, y);
            if (okx != oky || x != y)
                return fmt::format("memory at 0x{:08x}: {} (sequential) vs {} (pipelined)", addr, show(x), show(y));
        }
    std::size_t qi = 0;
    for (const auto& [ch, received] : used) {
        auto& q = queues[qi++];
        if (q[0]->popped() != q[1]->popped())
            return fmt::format("channel {}: {} words received (sequential) vs {} (pipelined)", ch, q[0]->popped(), q[1]->popped());
        const std::vector<std::uint32_t> x = q[0]->drain_all(), y = q[1]->drain_all();
        const std::size_t fed = received ? opts.fifo_words - q[0]->popped() : 0; // the unread input words come first
        for (std::size_t k = 0; k < std::max(x.size(), y.size()); ++k) {
            const bool hx = k < x.size(), hy = k < y.size();
            if (hx && hy && x[k] == y[k]) continue;
            const std::size_t word = k >= fed ? k - fed : k;
            return fmt::format("channel {}, word {} sent: {} (sequential) vs {} (pipelined)", ch, word,
                               hx ? show(x[k]) : std::string("none"), hy ? show(y[k]) : std::string("none"));
        }
    }
    for (const std::string& r : opts.registers) {
        if (r.size() < 2 || (r[0] != 'r' && r[0] != 'f')) continue;
        const auto f = r[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float;
        const std::uint32_t n = static_cast<std::uint32_t>(std::stoul(r.substr(1)));
        const std::uint32_t x = pa.reg(flat_reg(f, n)), y = pb.reg(flat_reg(f, n));
        if (x != y)
            return f == isa::RegFile::Int
                       ? fmt::format("{}: {} (sequential) vs {} (pipelined)", r, static_cast<std::int32_t>(x), static_cast<std::int32_t>(y))
                       : fmt::format("{}: {} (sequential) vs {} (pipelined)", r, show(x), show(y));
    }
    return std::nullopt;
}

} // namespace nesshi::iss
