// A fuzz input read as a stream of choices; zeros once it runs out, so every input is a program.
#pragma once

#include <cstddef>
#include <cstdint>

namespace nesshi::fuzz {

class Bytes {
  public:
    Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
    std::uint8_t next() { return i_ < n_ ? d_[i_++] : 0; }
    std::uint32_t word() {
        std::uint32_t w = 0;
        for (int k = 0; k < 4; ++k) w = w << 8 | next();
        return w;
    }
    std::uint64_t word64() { return std::uint64_t(word()) << 32 | word(); }
    bool done() const { return i_ >= n_; }

  private:
    const std::uint8_t* d_;
    std::size_t n_, i_ = 0;
};

} // namespace nesshi::fuzz
