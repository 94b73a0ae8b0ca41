// A set-associative cache with LRU replacement over a region (the IC's cache over ICGM): timing
// only, since the data are read-only. A miss stalls the access by `miss_cycles`.
#pragma once

#include "iss/memory.hpp"
#include "rt/machine.hpp"

#include <cstdint>
#include <vector>

namespace nesshi::rt::machine {

class SetAssocCache final : public iss::CacheModel {
  public:
    explicit SetAssocCache(const CacheOptions& o); // throws std::invalid_argument on a bad geometry
    std::uint32_t access(std::uint32_t addr, std::uint32_t bytes, bool write) override;
    std::uint64_t accesses() const { return accesses_; }
    std::uint64_t misses() const { return misses_; }

  private:
    std::uint32_t line_shift_ = 5, sets_ = 1, ways_ = 1, miss_cycles_ = 0;
    std::vector<std::uint32_t> tags_;  // sets x ways; tag + 1, 0 = invalid
    std::vector<std::uint64_t> stamp_; // last use, for LRU
    std::uint64_t now_ = 0, accesses_ = 0, misses_ = 0;
};

} // namespace nesshi::rt::machine
