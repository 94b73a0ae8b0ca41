// The IC cache model.
#include "iss/cache.hpp"

#include <bit>
#include <stdexcept>
#include <string>

namespace nesshi::iss {

SetAssocCache::SetAssocCache(const CacheGeometry& o) {
    if (!std::has_single_bit(o.line) || o.line < 4) throw std::invalid_argument("cache line must be a power of two >= 4");
    if (o.ways == 0 || o.bytes % (o.line * o.ways) != 0 || !std::has_single_bit(o.bytes / (o.line * o.ways)))
        throw std::invalid_argument("cache size must be line x ways x a power of two");
    line_shift_ = static_cast<std::uint32_t>(std::countr_zero(o.line));
    ways_ = o.ways;
    sets_ = o.bytes / (o.line * o.ways);
    miss_cycles_ = o.miss_cycles;
    tags_.assign(static_cast<std::size_t>(sets_) * ways_, 0);
    stamp_.assign(tags_.size(), 0);
}

std::uint32_t SetAssocCache::access(std::uint32_t addr, std::uint32_t, bool) {
    ++accesses_;
    ++now_;
    const std::uint32_t line = addr >> line_shift_;
    const std::uint32_t set = line & (sets_ - 1);
    const std::uint32_t tag = line + 1;
    std::uint32_t* t = &tags_[static_cast<std::size_t>(set) * ways_];
    std::uint64_t* s = &stamp_[static_cast<std::size_t>(set) * ways_];
    std::uint32_t victim = 0;
    for (std::uint32_t w = 0; w < ways_; ++w) {
        if (t[w] == tag) {
            s[w] = now_;
            return 0;
        }
        if (s[w] < s[victim]) victim = w;
    }
    ++misses_;
    t[victim] = tag;
    s[victim] = now_;
    return miss_cycles_;
}

} // namespace nesshi::iss
