// A FIFO queue in one growing power-of-two array: push at the back, pop at the front, index from
// the front. The FIFOs' words, held messages and receive cycles: std::deque allocated a block
// every few hundred words and cost more than the turn rule around it.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace nesshi::machine {

template <class T>
class Ring {
  public:
    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }
    T& front() { return buf_[head_]; }
    const T& front() const { return buf_[head_]; }
    const T& back() const { return (*this)[size_ - 1]; }
    T& operator[](std::size_t i) { return buf_[(head_ + i) & (buf_.size() - 1)]; }
    const T& operator[](std::size_t i) const { return buf_[(head_ + i) & (buf_.size() - 1)]; }

    void push_back(const T& v) {
        if (size_ == buf_.size()) grow();
        buf_[(head_ + size_) & (buf_.size() - 1)] = v;
        ++size_;
    }
    void pop_front() {
        head_ = (head_ + 1) & (buf_.size() - 1);
        --size_;
    }

  private:
    void grow() {
        std::vector<T> bigger(buf_.empty() ? 16 : 2 * buf_.size());
        for (std::size_t i = 0; i < size_; ++i) bigger[i] = std::move((*this)[i]);
        buf_ = std::move(bigger);
        head_ = 0;
    }

    std::vector<T> buf_;
    std::size_t head_ = 0, size_ = 0;
};

} // namespace nesshi::machine
