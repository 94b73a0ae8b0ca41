// The memory system of one processor: the machine's regions over sparse paged storage.
//
// Each region (OS SRAM, IC resident memory, global memory, ...) comes from the machine
// description. Storage is a PagedMemory: 4 KiB pages (and the page table itself) allocated on
// first write, so an untouched region costs nothing. A host shares one PagedMemory between
// processors (e.g. the IC global memory) with Processor::attach_memory; reads never allocate,
// so concurrent readers of read-only data are safe. Out-of-range and misaligned accesses are
// faults, never undefined behaviour. An optional CacheModel adds stall cycles per access.
#pragma once

#include "isa/machine.hpp"

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace nesshi::iss {

class PagedMemory {
  public:
    static constexpr uint32_t kPageBits = 12;
    static constexpr uint32_t kPageSize = 1u << kPageBits;

    explicit PagedMemory(uint32_t size);
    uint32_t size() const { return size_; }

    // Offsets are relative to the start of the storage; callers check bounds and alignment.
    uint32_t read(uint32_t off, uint32_t bytes) const {
        uint32_t page = off >> kPageBits;
        if (page >= pages_.size()) return 0; // page table not allocated yet: all zero
        const uint8_t* p = pages_[page].get();
        if (!p) return 0;
        uint32_t v = 0;
        std::memcpy(&v, p + (off & (kPageSize - 1)), bytes); // little-endian host assumed
        return v;
    }
    void write(uint32_t off, uint32_t bytes, uint32_t v) {
        if (pages_.empty()) pages_.resize((uint64_t{size_} + kPageSize - 1) >> kPageBits); // on first write
        auto& p = pages_[off >> kPageBits];
        if (!p) p = std::make_unique<uint8_t[]>(kPageSize); // zero-initialised
        std::memcpy(p.get() + (off & (kPageSize - 1)), &v, bytes);
    }
    void write_bytes(uint32_t off, std::span<const uint8_t> bytes);
    // The storage page holding offset `off`, or nullptr while it is unallocated. Allocated
    // pages never move or go away, so the pointer stays valid for the storage's lifetime.
    uint8_t* page_data(uint32_t off) const {
        uint32_t page = off >> kPageBits;
        return page < pages_.size() ? pages_[page].get() : nullptr;
    }
    size_t pages_in_use() const;
    // FNV-1a over the contents (zero pages and missing pages hash alike).
    uint64_t hash() const;

  private:
    uint32_t size_;
    std::vector<std::unique_ptr<uint8_t[]>> pages_;
};

// Optional timing model for a region: extra stall cycles of one access (0 = hit). During an
// access its processor's cycle() is the access's issue cycle, in every engine.
class CacheModel {
  public:
    virtual ~CacheModel() = default;
    virtual uint32_t access(uint32_t addr, uint32_t bytes, bool write) = 0;
};

struct MemRegion {
    isa::MemoryDesc desc;
    std::shared_ptr<PagedMemory> store;
    CacheModel* cache = nullptr; // not owned
};

enum class MemError : uint8_t { None, OutOfRange, Misaligned };

class MemorySystem {
  public:
    explicit MemorySystem(const isa::Machine& m);

    // Mutable access may change a region's storage or cache, so it empties the TLB.
    std::vector<MemRegion>& regions() {
        flush_tlb();
        return regions_;
    }
    const std::vector<MemRegion>& regions() const { return regions_; }
    MemRegion* region(std::string_view name);

    // A small direct-mapped translation cache for the engines' loads and stores: 4 KiB address
    // pages that lie wholly in one region with no latency and no cache model, whose storage
    // page exists. Such an access needs no region search and adds no stall, so a hit goes
    // straight to host memory; everything else takes the checked path (find, then fill_tlb).
    // tlb_hit: an aligned `Bytes`-wide access to a page in the TLB (one compare: an entry's tag
    // is its page's first address, and the access address keeps its alignment bits); tlb_data:
    // then its host address.
    template <uint32_t Bytes> bool tlb_hit(uint32_t addr) const {
        return tlb_entry(addr).tag == (addr & (~(PagedMemory::kPageSize - 1) | (Bytes - 1)));
    }
    uint8_t* tlb_data(uint32_t addr) const { return tlb_entry(addr).data + (addr & (PagedMemory::kPageSize - 1)); }
    // Inline, so that compiled runs built at run time (iss/compiled.hpp) call nothing of the binary.
    void fill_tlb(const MemRegion& r, uint32_t addr) const {
        constexpr uint32_t kPage = PagedMemory::kPageSize;
        const uint64_t page_start = addr & ~uint64_t{kPage - 1};
        if (r.desc.latency || r.cache || r.desc.base % kPage) return;
        if (page_start < r.desc.base || page_start + kPage > uint64_t{r.desc.base} + r.desc.size) return;
        uint8_t* data = r.store->page_data(uint32_t(page_start - r.desc.base));
        if (!data) return; // an unallocated page reads as zero until a write allocates it
        tlb_[(addr >> PagedMemory::kPageBits) & (kTlbEntries - 1)] = {uint32_t(page_start), data};
    }
    void flush_tlb() { tlb_.fill(TlbEntry{}); }

    // The region holding [addr, addr+bytes), or nullptr.
    const MemRegion* find(uint32_t addr, uint32_t bytes) const {
        for (const MemRegion& r : regions_)
            if (r.desc.contains(addr, bytes)) return &r;
        return nullptr;
    }
    MemError check(uint32_t addr, uint32_t bytes) const {
        if (addr & (bytes - 1)) return MemError::Misaligned;
        return find(addr, bytes) ? MemError::None : MemError::OutOfRange;
    }

    // Debugger / host access: false when out of range (alignment not required).
    bool peek(uint32_t addr, uint32_t bytes, uint32_t& out) const;
    bool poke(uint32_t addr, uint32_t bytes, uint32_t value);
    void load_data(uint32_t addr, std::span<const uint8_t> bytes); // throws LoadError (data_outside_memories)
    uint64_t hash() const;

  private:
    struct TlbEntry {
        uint32_t tag = UINT32_MAX; // the page's first address; never matches (its low bits are set)
        uint8_t* data = nullptr;
    };
    // 4 MiB of pages: the OS SRAM (2 MiB) and the IC's resident memory (1 MiB) of the presets fit
    // whole, so a fine grid's walk does not take the checked path (with 64 entries, 10 % of a
    // V render of balls at grid 100 went to load_checked and its memcpy).
    static constexpr uint32_t kTlbEntries = 1024;
    const TlbEntry& tlb_entry(uint32_t addr) const {
        return tlb_[(addr >> PagedMemory::kPageBits) & (kTlbEntries - 1)];
    }
    std::vector<MemRegion> regions_;
    mutable std::array<TlbEntry, kTlbEntries> tlb_{};
};

// The LoadError text for `bytes` bytes of data at `addr` that no memory of `memories` holds: "data
// section at 0x00400000 (5744 bytes) is outside every memory region[ of OWNER]: it starts in
// resident (0x00400000, 4096 bytes), which would need 5744 bytes to hold it" (the last part when it
// starts in one).
std::string data_outside_memories(const std::vector<isa::MemoryDesc>& memories, uint32_t addr, std::size_t bytes,
                                  const std::string& owner = "");

} // namespace nesshi::iss
