// FIFO channels: the interface a host implements to connect processors, and a simple queue.
//
// Words carry the cycle from which they can be received, so a consumer that runs ahead of
// its producer waits exactly until the word exists (deterministic whatever the host's
// scheduling order). A `recv` on a channel with no readable word blocks its whole bundle: the
// processor counts a wait cycle and retries. A `send` on a full channel blocks likewise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nesshi::iss {

class Channel {
  public:
    virtual ~Channel() = default;
    // Number of words receivable at `cycle` (words whose ready cycle <= cycle), counted up to
    // `enough`: the engine only asks whether a bundle's receives can all go, and a long queue
    // must not cost a scan per receive.
    //
    // The engines rely on two properties of readable() and writable() (a host's channel may
    // update its own state in them, as machine::Fifo does): between two operations on the
    // channel the answers do not depend on how often or in what order they are asked, and
    // readable(cycle, k) >= k exactly when k words are receivable (so it is monotone in k).
    // The threaded engine's fast gate asks once per channel and direction with all the words
    // the bundle moves; when that does not pass, the general gate asks again, op by op.
    virtual size_t readable(uint64_t cycle, size_t enough) const = 0;
    // Ready cycle of the front word; nullopt when the channel is empty.
    virtual std::optional<uint64_t> front_ready() const = 0;
    virtual uint32_t pop() = 0;
    // Free space; SIZE_MAX when unbounded.
    virtual size_t writable() const = 0;
    // Called with the cycle the sending bundle issues.
    virtual void push(uint32_t word, uint64_t cycle) = 0;
    // A bundle's words at once: when a bundle receives several words from this channel and from
    // no other, or sends several into it and into no other, the engines make one call with all of
    // them (at the bundle's first receive, at its last send), which must do what n pop()s, or n
    // push()es at `cycle`, in a row would do. A bundle issues whole, so the host sees no
    // difference but the count of calls.
    virtual void pop_n(uint32_t* out, size_t n) {
        for (size_t i = 0; i < n; ++i) out[i] = pop();
    }
    virtual void push_n(const uint32_t* words, size_t n, uint64_t cycle) {
        for (size_t i = 0; i < n; ++i) push(words[i], cycle);
    }
    // True when no word will ever arrive again (standalone input files): receiving from an
    // empty closed channel is a deadlock, not a wait.
    virtual bool closed() const { return false; }
};

// An in-memory FIFO: unbounded by default; `latency` cycles between send and receive.
class QueueChannel : public Channel {
  public:
    explicit QueueChannel(size_t capacity = std::numeric_limits<size_t>::max(), uint32_t latency = 1)
        : capacity_(capacity), latency_(latency) {}

    size_t readable(uint64_t cycle, size_t enough) const override;
    std::optional<uint64_t> front_ready() const override;
    uint32_t pop() override;
    size_t writable() const override { return capacity_ - words_.size(); }
    void push(uint32_t word, uint64_t cycle) override;
    bool closed() const override { return closed_; }

    // Host side.
    void feed(uint32_t word, uint64_t ready_cycle = 0) { words_.push_back({word, ready_cycle}); }
    void close() { closed_ = true; }
    size_t size() const { return words_.size(); }
    std::vector<uint32_t> drain_all();
    uint64_t pushed() const { return pushed_; }
    uint64_t popped() const { return popped_; }

  private:
    struct Word { uint32_t value; uint64_t ready; };
    std::deque<Word> words_;
    size_t capacity_;
    uint32_t latency_;
    bool closed_ = false;
    uint64_t pushed_ = 0, popped_ = 0;
};

// Word files for `nesshi sim --fifo-in/--fifo-out`: whitespace-separated tokens, `#` starts a
// comment. A token is an integer (decimal, or 0x hex; negative allowed) or a float (has a
// '.', an exponent, or is inf/nan), stored as its binary32 bits. Throws std::runtime_error
// with file:line on a bad token.
std::vector<uint32_t> parse_words(std::string_view text, std::string_view name);
// Reads through base::read_file, whose base::Error (a std::runtime_error) it lets through.
std::vector<uint32_t> read_word_file(const std::string& path);
// "[CH=]FILE" as `nesshi sim --fifo-in/--fifo-out` and `nesshi debug --fifo-in` take it: the
// channel and the file, the channel `default_channel` when the spec does not start with
// "DIGITS=". A spec that starts with a digit and has an '=' names a channel: CH must be a decimal
// number 0..4294967295 and FILE must not be empty, else std::invalid_argument says what is wrong.
std::pair<uint32_t, std::string> parse_channel_spec(std::string_view spec, uint32_t default_channel);
// One word per line: "0x3f800000  # 1065353216 1.0"; parse_words reads it back.
std::string format_words(const std::vector<uint32_t>& words);

} // namespace nesshi::iss
