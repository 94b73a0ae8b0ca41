// A set-associative cache with LRU replacement over a region (the IC's cache over ICGM): timing
// only, since the data are read-only. A miss stalls the access by `miss_cycles`.
#pragma once

#include "iss/memory.hpp"

#include <cstdint>
#include <vector>

namespace nesshi::iss {

// The cache's shape; the defaults are the paper's IC cache (1 MB).
struct CacheGeometry {
    std::uint32_t bytes = 1u << 20;   // capacity
    std::uint32_t line = 32;          // bytes per line
    std::uint32_t ways = 4;
    std::uint32_t miss_cycles = 20;   // stall per miss
};

class SetAssocCache final : public iss::CacheModel {
  public:
    explicit SetAssocCache(const CacheGeometry& o); // throws std::invalid_argument on a bad geometry
    std::uint32_t access(std::uint32_t addr, std::uint32_t bytes, bool write) override;
    std::uint64_t accesses() const { return accesses_; }
    std::uint64_t misses() const { return misses_; }

  private:
    std::uint32_t line_shift_ = 5, sets_ = 1, ways_ = 1, miss_cycles_ = 0;
    std::vector<std::uint32_t> tags_;  // sets x ways; tag + 1, 0 = invalid
    std::vector<std::uint64_t> stamp_; // last use, for LRU
    std::uint64_t now_ = 0, accesses_ = 0, misses_ = 0;
};

} // namespace nesshi::iss
