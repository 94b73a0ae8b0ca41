// A FIFO between two stages of one PE. Each word carries the cycle from which it can be
// received (send cycle + 1 + the link's extra latency), so a consumer running ahead of its
// producer waits exactly until the word exists. Capacity counts words sent and not yet received.
#pragma once

#include "iss/channel.hpp"
#include "iss/processor.hpp"

#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>

namespace nesshi::machine {

class Fifo final : public iss::Channel {
  public:
    Fifo(std::size_t capacity, std::uint32_t extra_latency)
        : capacity_(capacity ? capacity : std::numeric_limits<std::size_t>::max()), latency_(1 + extra_latency) {}

    // iss::Channel (the simulated processors' side)
    std::size_t readable(std::uint64_t cycle, std::size_t enough) const override {
        std::size_t n = 0;
        for (const Word& w : words_) {
            if (w.ready > cycle || n == enough) break;
            ++n;
        }
        return n;
    }
    std::optional<std::uint64_t> front_ready() const override {
        if (words_.empty()) return std::nullopt;
        return words_.front().ready;
    }
    std::uint32_t pop() override {
        const std::uint32_t v = words_.front().value;
        words_.pop_front();
        room_cycle = 1 + (consumer_proc ? consumer_proc->cycle() : consumer_clock ? *consumer_clock : 0);
        return v;
    }
    std::size_t writable() const override { return capacity_ - std::min(capacity_, words_.size()); }
    void push(std::uint32_t word, std::uint64_t cycle) override { put(word, cycle + latency_); }

    // Host side: the SC model, the distributor, the scheduler.
    void send_at(std::uint32_t word, std::uint64_t cycle) { put(word, cycle + latency_); }
    std::size_t size() const { return words_.size(); }
    bool empty() const { return words_.empty(); }
    std::uint32_t word(std::size_t i) const { return words_[i].value; }
    std::uint64_t ready(std::size_t i) const { return words_[i].ready; }
    // Words from two producers interleave in push order, so ready times need not be monotone.
    bool all_ready(std::uint64_t cycle) const {
        return std::all_of(words_.begin(), words_.end(), [cycle](const Word& w) { return w.ready <= cycle; });
    }
    std::size_t max_size() const { return max_size_; }
    std::uint64_t pushed() const { return pushed_; }
    // The cycle after the consumer's last receive: the earliest cycle a producer held on a full
    // FIFO can go on. The consumer is a processor or the SC model (its clock).
    std::uint64_t room_cycle = 0;
    const iss::Processor* consumer_proc = nullptr;
    const std::uint64_t* consumer_clock = nullptr;

  private:
    struct Word {
        std::uint32_t value;
        std::uint64_t ready;
    };
    void put(std::uint32_t v, std::uint64_t ready) {
        words_.push_back({v, ready});
        max_size_ = std::max(max_size_, words_.size());
        ++pushed_;
    }
    std::deque<Word> words_;
    std::size_t capacity_;
    std::uint32_t latency_;
    std::size_t max_size_ = 0;
    std::uint64_t pushed_ = 0;
};

} // namespace nesshi::machine
