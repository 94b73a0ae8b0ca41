// FNV-1a, 64 bits: the one content hash of the project (machine fingerprints, the provenance of
// stored results). Not cryptographic: it tells versions apart, it does not resist forgery.
//
//   base::Fnv1a h;  h.add("os/dda.s");  h.add(text);  std::string id = base::hex64(h.value());
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace nesshi::base {

class Fnv1a {
  public:
    Fnv1a& add(std::string_view bytes) {
        for (unsigned char c : bytes) h_ = (h_ ^ c) * 1099511628211ull;
        return *this;
    }
    std::uint64_t value() const { return h_; }

  private:
    std::uint64_t h_ = 14695981039346656037ull;
};

inline std::uint64_t fnv1a64(std::string_view bytes) { return Fnv1a().add(bytes).value(); }

// Sixteen lower-case hex digits.
inline std::string hex64(std::uint64_t v) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, v >>= 4) s[static_cast<std::size_t>(i)] = kDigits[v & 15];
    return s;
}

} // namespace nesshi::base
