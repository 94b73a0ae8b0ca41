// A FIFO between two stages of one PE. Each word carries the cycle from which it can be
// received (send cycle + 1 + the link's extra latency), so a consumer running ahead of its
// producer waits exactly until the word exists. Capacity counts words sent and not yet received.
#pragma once

#include "iss/channel.hpp"

#include <algorithm>
#include <cstdint>
#include <deque>
#include <limits>

namespace nesshi::rt::machine {

class Fifo final : public iss::Channel {
  public:
    Fifo(std::size_t capacity, std::uint32_t extra_latency)
        : capacity_(capacity ? capacity : std::numeric_limits<std::size_t>::max()), latency_(1 + extra_latency) {}

    // iss::Channel (the simulated processors' side)
    std::size_t readable(std::uint64_t cycle) const override {
        std::size_t n = 0;
        for (const Word& w : words_) {
            if (w.ready > cycle) break;
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
    std::size_t max_size() const { return max_size_; }
    std::uint64_t pushed() const { return pushed_; }
    // When the consumer last made room (its clock at the end of the chunk that received): the
    // earliest cycle a producer held on a full FIFO can go on.
    std::uint64_t room_cycle = 0;

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

} // namespace nesshi::rt::machine
