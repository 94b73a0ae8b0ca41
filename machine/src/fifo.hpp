// A FIFO between stages of one PE. Each word carries the cycle from which it can be received
// (send cycle + 1 + the link's extra latency), so a consumer running ahead of its producer waits
// exactly until the word exists. Capacity counts words sent and not yet received.
//
// Pipelined models follow the turn rule (turns.hpp): the consumer's gates and the processor
// producer's gates answer "nothing yet" / "no room" when their stage does not have the turn, so
// words enter in the order of their send cycles and every action sees the FIFO as it is at its
// cycle. DIS sends eye rays on its own link ahead of SC's clock: those messages are held and
// enter behind everything sent before their first word. Messages never interleave: a message
// enters whole, at its first word's send cycle.
#pragma once

#include "ring.hpp"
#include "turns.hpp"

#include "iss/channel.hpp"
#include "iss/processor.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>

namespace nesshi::machine {

class Fifo final : public iss::Channel {
  public:
    static constexpr std::uint64_t kNone = ~std::uint64_t{0};

    Fifo(std::size_t capacity, std::uint32_t extra_latency)
        : capacity_(capacity ? capacity : std::numeric_limits<std::size_t>::max()), bounded_(capacity != 0),
          latency_(1 + extra_latency) {}

    // Who acts on it, for the turn rule; without a call (model S) every gate answers at once.
    void follow_turns(Turns* t, int consumer, int producer, int host_producer = -1) {
        turns_ = t;
        consumer_ = consumer;
        producer_ = producer;
        host_producer_ = host_producer;
    }

    // iss::Channel, the consumer's side.
    // A word sent is in its final place (sends into this FIFO follow the turn rule, or there is
    // one producer): the consumer needs its turn only to wait for words not sent yet, to let held
    // messages enter, or to free room that a producer may be waiting for.
    std::size_t readable(std::uint64_t cycle, std::size_t enough) const override {
        asked_ = enough;
        if (!may_act(consumer_, cycle)) {
            if (bounded_ || words_.size() < enough) return 0;
        } else {
            release(cycle);
        }
        std::size_t n = 0;
        while (n < words_.size() && n < enough && words_[n].ready <= cycle) ++n;
        return n;
    }
    std::optional<std::uint64_t> front_ready() const override {
        const std::uint64_t now = consumer_now();
        if (!may_act(consumer_, now)) {
            if (bounded_ || words_.size() < asked_) return std::nullopt;
        } else {
            release(now);
        }
        if (words_.empty()) return std::nullopt;
        return words_.front().ready;
    }
    std::uint32_t pop() override {
        std::uint32_t v;
        take(&v, 1);
        return v;
    }
    void pop_n(std::uint32_t* out, std::size_t n) override { take(out, n); }
    // The producer processor's side.
    std::size_t writable() const override {
        // One producer and no capacity: its words enter in its own order and nothing limits it.
        if (!bounded_ && host_producer_ < 0) return std::numeric_limits<std::size_t>::max();
        const std::uint64_t now = producer_now();
        if (!may_act(producer_, now)) return 0;
        release(now);
        return room_at(now);
    }
    void push(std::uint32_t word, std::uint64_t cycle) override { put_n(&word, 1, cycle); }
    void push_n(const std::uint32_t* words, std::size_t n, std::uint64_t cycle) override { put_n(words, n, cycle); }

    // Host side (SC and DIS, stage host_producer): a message of words sent one per cycle from
    // `first`; `ahead` (DIS) when `first` may be past the acting stage's cycle.
    void send(std::span<const std::uint32_t> msg, std::uint64_t first, bool ahead) {
        if (ahead && turns_) {
            for (std::size_t i = 0; i < msg.size(); ++i) held_.push_back({msg[i], first + i + latency_, first});
            note_size();
        } else {
            release(first);
            for (std::size_t i = 0; i < msg.size(); ++i) put(msg[i], first + i + latency_);
        }
        pushed_ += ahead && turns_ ? msg.size() : 0;
        if (turns_) turns_->enables(host_producer_, consumer_, std::max(first + latency_, consumer_now()));
    }
    // Room for a sender acting at `now`: words sent before it and not received before it.
    std::size_t room_at(std::uint64_t now) const {
        if (!bounded_) return std::numeric_limits<std::size_t>::max();
        const std::size_t used = words_.size() + held_.size() + pops_since(now);
        return capacity_ - std::min(capacity_, used);
    }
    // The earliest cycle from `now` at which `need` words fit, from the receives so far; kNone
    // when only receives still to come can make room.
    std::uint64_t room_from(std::uint64_t now, std::size_t need) const {
        if (!bounded_) return now;
        const std::size_t base = words_.size() + held_.size();
        if (capacity_ < base + need) return kNone;
        const std::size_t spare = capacity_ - base - need; // receives at or after the cycle that may still count
        if (pops_since(now) <= spare) return now;
        return pops_[pops_.size() - spare - 1] + 1;
    }

    bool bounded() const { return bounded_; }
    std::uint32_t latency() const { return latency_; }
    std::size_t size() const { return words_.size(); }
    std::size_t held() const { return held_.size(); }
    bool empty() const { return words_.empty(); }
    std::uint32_t word(std::size_t i) const { return words_[i].value; }
    std::uint64_t ready(std::size_t i) const { return words_[i].ready; }
    // The cycle the n-th word waiting (1-based, sent or held) can be received: kNone when fewer
    // are known. Held words come after every sent one.
    std::uint64_t arrival(std::size_t n) const {
        if (n <= words_.size()) return words_[n - 1].ready;
        if (n <= words_.size() + held_.size()) return held_[n - words_.size() - 1].ready;
        return kNone;
    }
    bool all_ready(std::uint64_t cycle) const {
        for (std::size_t i = 0; i < words_.size(); ++i)
            if (words_[i].ready > cycle) return false;
        return true;
    }
    // The most words sent and not yet received (under the turn rule counted at each receive, as
    // a sender may run ahead of its consumer; else at each send).
    std::size_t max_size() const { return std::max(max_size_, words_.size() + held_.size()); }
    std::uint64_t pushed() const { return pushed_; }
    // The cycle after the consumer's last receive: the earliest cycle a producer held on a full
    // FIFO can go on. The consumer is a processor or the SC model (its clock).
    std::uint64_t room_cycle = 0;
    const iss::Processor* consumer_proc = nullptr;
    const std::uint64_t* consumer_clock = nullptr;
    const iss::Processor* producer_proc = nullptr;

  private:
    struct Word {
        std::uint32_t value;
        std::uint64_t ready;
    };
    struct Held {
        std::uint32_t value;
        std::uint64_t ready, first; // `first`: the send cycle of its message's first word
    };
    // n receives at the consumer's cycle, as n pop()s: the first one releases held messages and
    // counts the most words waiting (each later one finds one fewer); the room they free and
    // the turns they hand on are the same for all.
    void take(std::uint32_t* out, std::size_t n) {
        const std::uint64_t now = consumer_now();
        if (may_act(consumer_, now)) release(now);
        // (The words sent by `now` are at most all of them: when those cannot beat the most so
        // far, the count of sent words need not move on.)
        if (turns_ && words_.size() + held_.size() > max_size_)
            max_size_ = std::max(max_size_, sent_by(now) + held_.size());
        for (std::size_t i = 0; i < n; ++i) {
            out[i] = words_.front().value;
            words_.pop_front();
        }
        sent_ -= std::min(sent_, n);
        room_cycle = now + 1;
        if (turns_ && bounded_) {
            for (std::size_t i = 0; i < n; ++i) {
                pops_.push_back(now);
                if (pops_.size() > 2 * capacity_ + 16) pops_.pop_front();
            }
            for (int p : {producer_, host_producer_})
                if (p >= 0 && turns_->wants_room[p])
                    turns_->enables(consumer_, p, std::max(now + 1, p == host_producer_ ? 0 : producer_now()));
        }
    }
    // n sends in the bundle issued at `cycle`, as n push()es: the turn they hand the consumer is
    // the same for all.
    void put_n(const std::uint32_t* words, std::size_t n, std::uint64_t cycle) {
        release(cycle);
        for (std::size_t i = 0; i < n; ++i) words_.push_back({words[i], cycle + latency_});
        pushed_ += n;
        note_size();
        // The consumer may act from the word's arrival (not before its own clock); usually the
        // message's first word has lowered the horizon already.
        if (turns_ && cycle + latency_ <= turns_->horizon[producer_])
            turns_->enables(producer_, consumer_, std::max(cycle + latency_, consumer_now()));
    }
    bool may_act(int stage, std::uint64_t cycle) const { return !turns_ || turns_->may_act(stage, cycle); }
    // A stage's clock: it acts at no earlier cycle, whatever it is sent.
    std::uint64_t producer_now() const { return producer_proc ? producer_proc->cycle() : 0; }
    std::uint64_t consumer_now() const {
        return consumer_proc ? consumer_proc->cycle() : consumer_clock ? *consumer_clock : 0;
    }
    // Held messages whose first word is sent by `now` enter (the turn rule: nothing sent before
    // them is still to come). Mutable state: the Channel's queries are const.
    void release(std::uint64_t now) const {
        while (!held_.empty() && held_.front().first <= now) {
            words_.push_back({held_.front().value, held_.front().ready});
            held_.pop_front();
        }
    }
    std::size_t pops_since(std::uint64_t now) const {
        std::size_t n = 0;
        while (n < pops_.size() && pops_[pops_.size() - 1 - n] >= now) ++n;
        return n;
    }
    void put(std::uint32_t v, std::uint64_t ready) {
        words_.push_back({v, ready});
        ++pushed_;
        note_size();
    }
    void note_size() {
        if (!turns_) max_size_ = std::max(max_size_, words_.size() + held_.size());
    }
    // Words sent by cycle `now`: all of them with several producers (they send in turn), else
    // those whose send cycle has come (one producer's words arrive in order).
    std::size_t sent_by(std::uint64_t now) {
        if (host_producer_ >= 0) return words_.size();
        while (sent_ < words_.size() && words_[sent_].ready <= now + latency_) ++sent_;
        return sent_;
    }

    mutable std::size_t asked_ = 1; // words the consumer's bundle receives (its last readable())
    mutable Ring<Word> words_;
    mutable Ring<Held> held_;
    Ring<std::uint64_t> pops_; // cycles of the latest receives (bounded FIFOs under the turn rule)
    std::size_t capacity_;
    bool bounded_;
    std::uint32_t latency_;
    Turns* turns_ = nullptr;
    int consumer_ = 0, producer_ = -1, host_producer_ = -1;
    std::size_t max_size_ = 0;
    std::size_t sent_ = 0; // one producer: words from the front known sent (counted on at a receive that may set a new most)
    std::uint64_t pushed_ = 0;
};

} // namespace nesshi::machine
