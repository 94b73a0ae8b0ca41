// Paged storage and the region map of one processor (see memory.hpp).
#include "iss/memory.hpp"

#include "iss/program.hpp"

#include <fmt/core.h>

namespace nesshi::iss {

PagedMemory::PagedMemory(uint32_t size) : size_(size) {}

void PagedMemory::write_bytes(uint32_t off, std::span<const uint8_t> bytes) {
    for (size_t i = 0; i < bytes.size(); ++i) write(uint32_t(off + i), 1, bytes[i]);
}

size_t PagedMemory::pages_in_use() const {
    size_t n = 0;
    for (const auto& p : pages_) n += p != nullptr;
    return n;
}

uint64_t PagedMemory::hash() const {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < pages_.size(); ++i) {
        const uint8_t* p = pages_[i].get();
        if (!p) continue;
        bool zero = true;
        for (uint32_t k = 0; k < kPageSize && zero; ++k) zero = p[k] == 0;
        if (zero) continue;
        h = (h ^ i) * 1099511628211ull;
        for (uint32_t k = 0; k < kPageSize; ++k) h = (h ^ p[k]) * 1099511628211ull;
    }
    return h;
}

MemorySystem::MemorySystem(const isa::Machine& m) {
    for (const auto& d : m.memories) regions_.push_back({d, std::make_shared<PagedMemory>(d.size), nullptr});
}

MemRegion* MemorySystem::region(std::string_view name) {
    flush_tlb();
    for (MemRegion& r : regions_)
        if (r.desc.name == name) return &r;
    return nullptr;
}

bool MemorySystem::peek(uint32_t addr, uint32_t bytes, uint32_t& out) const {
    const MemRegion* r = find(addr, bytes);
    if (!r) return false;
    out = 0;
    for (uint32_t i = 0; i < bytes; ++i) out |= r->store->read(addr - r->desc.base + i, 1) << (8 * i);
    return true;
}

bool MemorySystem::poke(uint32_t addr, uint32_t bytes, uint32_t value) {
    const MemRegion* r = find(addr, bytes);
    if (!r) return false;
    for (uint32_t i = 0; i < bytes; ++i) r->store->write(addr - r->desc.base + i, 1, (value >> (8 * i)) & 0xff);
    return true;
}

std::string data_outside_memories(const std::vector<isa::MemoryDesc>& memories, uint32_t addr, std::size_t bytes,
                                  const std::string& owner) {
    std::string where; // the memory it starts in, and what would hold it
    for (const isa::MemoryDesc& m : memories)
        if (addr >= m.base && addr - m.base < m.size)
            where = fmt::format(": it starts in {} (0x{:08x}, {} bytes), which would need {} bytes to hold it", m.name, m.base,
                                m.size, std::uint64_t{addr - m.base} + bytes);
    return fmt::format("data section at 0x{:08x} ({} bytes) is outside every memory region{}{}", addr, bytes,
                       owner.empty() ? "" : " of " + owner, where);
}

void MemorySystem::load_data(uint32_t addr, std::span<const uint8_t> bytes) {
    if (bytes.empty()) return;
    if (bytes.size() > UINT32_MAX) throw LoadError("data section too large");
    const MemRegion* r = find(addr, uint32_t(bytes.size()));
    if (!r) {
        std::vector<isa::MemoryDesc> memories;
        for (const MemRegion& m : regions_) memories.push_back(m.desc);
        throw LoadError(data_outside_memories(memories, addr, bytes.size()));
    }
    r->store->write_bytes(addr - r->desc.base, bytes);
}

uint64_t MemorySystem::hash() const {
    uint64_t h = 1469598103934665603ull;
    for (const MemRegion& r : regions_) h = (h ^ r.store->hash()) * 1099511628211ull;
    return h;
}

} // namespace nesshi::iss
