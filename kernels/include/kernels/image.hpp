// Host side of the kernel ABI: lays a grid and its shape records out as OS SRAM and IC memory
// images (abi.hpp), and converts between padded map addresses and voxel coordinates.
#pragma once

#include "kernels/abi.hpp"
#include "kernels/dispatch.hpp"
#include "kernels/messages.hpp"
#include "kernels/shape_record.hpp"
#include "kernels/twins/dda.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace nesshi::kernels {

// A memory image: bytes to place at `base`.
struct MemImage {
    std::uint32_t base = 0;
    std::vector<std::uint8_t> bytes;
    void put32(std::uint32_t addr, std::uint32_t v) {
        const std::size_t off = addr - base;
        if (off + 4 > bytes.size()) bytes.resize(off + 4);
        std::memcpy(bytes.data() + off, &v, 4);
    }
    void putf(std::uint32_t addr, float f) { put32(addr, abi::bits(f)); }
};

struct PaddedGrid {
    int n[3] = {1, 1, 1};
    std::uint32_t stride[3] = {1, 3, 9};
    std::uint32_t voxels() const { return stride[2] * static_cast<std::uint32_t>(n[2] + 2); }
    // padded index of voxel (ix, iy, iz); -1 .. n are valid coordinates (the frame)
    std::uint32_t index(int ix, int iy, int iz) const {
        return static_cast<std::uint32_t>(ix + 1) * stride[0] + static_cast<std::uint32_t>(iy + 1) * stride[1] +
               static_cast<std::uint32_t>(iz + 1) * stride[2];
    }
    std::uint32_t unpadded(int ix, int iy, int iz) const {
        return static_cast<std::uint32_t>((iz * n[1] + iy) * n[0] + ix);
    }
};

inline PaddedGrid padded(const twins::GridGeom& g) {
    PaddedGrid p;
    for (int k = 0; k < 3; ++k) p.n[k] = g.n[k];
    p.stride[0] = 1;
    p.stride[1] = static_cast<std::uint32_t>(g.n[0] + 2);
    p.stride[2] = p.stride[1] * static_cast<std::uint32_t>(g.n[1] + 2);
    return p;
}

// OS SRAM image (from address 0): geometry block, empty state table, padded occupancy map.
// `occupancy` is the unpadded map of rt/grid.hpp (x fastest).
inline MemImage os_image(const twins::GridGeom& g, const std::vector<std::uint8_t>& occupancy) {
    const PaddedGrid p = padded(g);
    if (!abi::os_sram_fits(g.n[0], g.n[1], g.n[2])) throw std::runtime_error("grid too large for OS SRAM");
    MemImage m;
    m.base = 0;
    m.bytes.assign(abi::kOsOcc + p.voxels(), 0);
    for (int k = 0; k < 3; ++k) {
        const auto a = static_cast<std::uint32_t>(4 * k);
        m.putf(abi::get("GEOM_LO") + a, g.lo[k]);
        m.putf(abi::get("GEOM_HI") + a, g.hi[k]);
        m.putf(abi::get("GEOM_CELL") + a, g.cell[k]);
        m.putf(abi::get("GEOM_INV_CELL") + a, g.inv_cell[k]);
        m.putf(abi::get("GEOM_NMAX") + a, static_cast<float>(g.n[k] - 1));
        m.put32(abi::get("GEOM_N") + a, static_cast<std::uint32_t>(g.n[k]));
        m.put32(abi::get("GEOM_STRIDE") + a, p.stride[k]);
    }
    m.put32(abi::get("GEOM_OCC0"), abi::kOsOcc + p.index(0, 0, 0));
    std::uint8_t* map = m.bytes.data() + abi::kOsOcc;
    for (int z = -1; z <= g.n[2]; ++z)
        for (int y = -1; y <= g.n[1]; ++y)
            for (int x = -1; x <= g.n[0]; ++x) {
                const bool in = x >= 0 && y >= 0 && z >= 0 && x < g.n[0] && y < g.n[1] && z < g.n[2];
                map[p.index(x, y, z)] = in ? (occupancy[p.unpadded(x, y, z)] ? abi::kOccFull : abi::kOccEmpty)
                                           : abi::kOccBorder;
            }
    return m;
}

// IC memory image: header at IC_HEADER, then (from IC_DATA) the END record (and the LOOPS record
// for a hybrid kernel), the shape records, the voxel table (one word per padded voxel) and the
// END-terminated lists. Everything goes to
// resident memory when it fits; else the most-referenced records do (ic_image_lists).
// `offsets`/`prims` are rt/grid.hpp's unpadded offsets and shape-index lists.
struct IcImage {
    MemImage resident, global;
    std::uint32_t records = 0; // address of shape record 0
    std::uint32_t end_record = 0;
};

// How an IC kernel wants its voxel lists laid out (kbuild::list_layout reads it off the program).
struct ListLayout {
    bool by_kind = false;        // every list kind by kind (stably, by dispatch code)
    std::uint32_t long_from = 0; // hybrid: lists of at least this many references start with the
                                 // LOOPS record and go kind by kind; 0: none
    bool reads_ahead() const { return by_kind || long_from > 0; }
    bool operator==(const ListLayout&) const = default;
};

// Writes the voxel table at `tab` and the END-terminated lists from `lists_at` into `d`;
// addr[i] is the address of shape i's record. A list in `loops` starts with `loops_record`.
inline void put_lists(MemImage& d, std::uint32_t tab, std::uint32_t lists_at,
                      const std::vector<std::vector<std::uint32_t>>& lists, const std::vector<std::uint32_t>& addr,
                      std::uint32_t end_record, std::uint32_t read_ahead = 1, const std::vector<bool>& loops = {},
                      std::uint32_t loops_record = 0) {
    std::uint32_t cursor = lists_at;
    for (std::size_t v = 0; v < lists.size(); ++v) {
        d.put32(tab + 4 * static_cast<std::uint32_t>(v), cursor);
        if (v < loops.size() && loops[v]) {
            d.put32(cursor, loops_record);
            cursor += 4;
        }
        for (std::uint32_t si : lists[v]) {
            d.put32(cursor, addr[si]);
            cursor += 4;
        }
        d.put32(cursor, end_record);
        cursor += 4;
    }
    for (std::uint32_t k = 0; k < read_ahead; ++k, cursor += 4) d.put32(cursor, end_record); // words the kernel reads ahead
}

inline void put_record(MemImage& d, std::uint32_t r, const kernels::Shape& s, std::uint32_t index) {
    d.put32(r, shape_code(s));
    d.put32(r + 4, static_cast<std::uint32_t>(s.entity));
    for (int w = 0; w < 18; ++w) d.putf(r + 8 + 4 * static_cast<std::uint32_t>(w), s.w[static_cast<std::size_t>(w)]);
    d.put32(r + static_cast<std::uint32_t>(abi::get("REC_INDEX")), index);
}

// Lists given directly: lists[v] = shape indices of padded voxel v (empty for the frame).
// Placement: everything in resident memory when it fits (records in index order, then table and
// lists); else, with `allow_resident`, the END record and the most-referenced shape records (by
// the number of voxel lists holding them, ties to the lower index) fill resident memory and the
// rest of the records, the table and the lists go to global memory; without it, all to global.
// The kernel follows addresses only, so placement changes timing (with a cache), never results.
// `layout.by_kind`: each list in order of dispatch code, stably (for a kernel that defines
// abi::kListsByKindLabel; it breaks ties on shape indices itself), followed by abi::kListReadAhead
// END entries; `layout.long_from`: only the lists that long, each after a LOOPS entry (a hybrid
// kernel, abi::kListsLongPrefix).
inline IcImage ic_image_lists(std::vector<std::vector<std::uint32_t>> lists, const std::vector<kernels::Shape>& shapes,
                              bool allow_resident = true, ListLayout layout = {}) {
    std::vector<bool> kind_order(lists.size(), layout.by_kind); // the loops read the list kind by kind
    if (layout.long_from > 0)
        for (std::size_t v = 0; v < lists.size(); ++v) kind_order[v] = lists[v].size() >= layout.long_from;
    std::size_t refs = 0, marked = 0;
    for (std::size_t v = 0; v < lists.size(); ++v) {
        if (kind_order[v])
            std::stable_sort(lists[v].begin(), lists[v].end(),
                             [&](std::uint32_t a, std::uint32_t b) { return shape_code(shapes[a]) < shape_code(shapes[b]); });
        refs += lists[v].size();
        marked += layout.long_from > 0 && kind_order[v];
    }
    refs += marked; // each long list's LOOPS entry
    const std::uint32_t limit = static_cast<std::uint32_t>(abi::get("IC_RESIDENT_LIMIT"));
    const std::uint32_t read_ahead = layout.reads_ahead() ? abi::kListReadAhead : 1;
    // Beyond abi::ic_data_bytes (which counts one read-ahead word): the other read-ahead words and
    // the LOOPS record. (machine::memory_report counts without them: for a kernel that reads
    // ahead it may say "fits resident" of data a few hundred bytes short of fitting.)
    const std::uint64_t beyond = (read_ahead - 1) * 4ull + (layout.long_from > 0 ? abi::kRecBytes : 0);
    const bool all_resident =
        allow_resident && abi::kIcData + abi::ic_data_bytes(shapes.size(), lists.size(), refs) + beyond <= limit;
    IcImage im;
    im.resident.base = abi::kIcHeader;
    im.global.base = abi::kIcGlobal;
    std::uint32_t res = abi::kIcData, glob = abi::kIcGlobal;
    MemImage& main = all_resident ? im.resident : im.global;
    std::uint32_t& cursor = all_resident ? res : glob;
    // END record: resident whenever resident memory is used at all (every list ends with it).
    MemImage& end_image = allow_resident ? im.resident : im.global;
    std::uint32_t& end_cursor = allow_resident ? res : glob;
    im.end_record = end_cursor;
    end_image.put32(end_cursor + static_cast<std::uint32_t>(abi::get("REC_CODE")),
                    static_cast<std::uint32_t>(abi::get("CODE_END")));
    end_image.put32(end_cursor + abi::kRecBytes - 4, 0);
    end_cursor += abi::kRecBytes;
    std::uint32_t loops_record = 0; // beside END: a hybrid kernel prefetches its payload as a shape's
    if (layout.long_from > 0) {
        loops_record = end_cursor;
        end_image.put32(end_cursor + static_cast<std::uint32_t>(abi::get("REC_CODE")),
                        static_cast<std::uint32_t>(abi::get("CODE_LOOPS")));
        end_image.put32(end_cursor + abi::kRecBytes - 4, 0);
        end_cursor += abi::kRecBytes;
    }
    std::vector<std::uint32_t> addr(shapes.size());
    if (allow_resident && !all_resident) { // hot records first
        std::vector<std::uint32_t> count(shapes.size(), 0), order(shapes.size());
        for (const auto& l : lists)
            for (std::uint32_t si : l) ++count[si];
        for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return count[a] > count[b]; });
        for (std::uint32_t si : order) {
            const bool fits = res + abi::kRecBytes <= limit;
            std::uint32_t& c = fits ? res : glob;
            addr[si] = c;
            put_record(fits ? im.resident : im.global, c, shapes[si], si);
            c += abi::kRecBytes;
        }
    } else {
        for (std::uint32_t i = 0; i < shapes.size(); ++i) {
            addr[i] = cursor;
            put_record(main, cursor, shapes[i], i);
            cursor += abi::kRecBytes;
        }
    }
    im.records = shapes.empty() ? cursor : addr[0];
    const std::uint32_t tab = cursor;
    cursor += static_cast<std::uint32_t>(lists.size()) * 4;
    put_lists(main, tab, cursor, lists, addr, im.end_record, read_ahead, layout.long_from > 0 ? kind_order : std::vector<bool>{},
              loops_record);
    im.resident.put32(abi::kIcHeader + static_cast<std::uint32_t>(abi::get("ICH_VOXTAB")), tab);
    im.resident.put32(abi::kIcHeader + static_cast<std::uint32_t>(abi::get("ICH_END_REC")), im.end_record);
    return im;
}

// From rt/grid.hpp's unpadded offsets and shape-index lists.
inline IcImage ic_image(const twins::GridGeom& g, const std::vector<std::uint32_t>& offsets,
                        const std::vector<std::uint32_t>& prims, const std::vector<kernels::Shape>& shapes,
                        bool allow_resident = true, ListLayout layout = {}) {
    const PaddedGrid p = padded(g);
    std::vector<std::vector<std::uint32_t>> lists(p.voxels());
    for (int z = 0; z < p.n[2]; ++z)
        for (int y = 0; y < p.n[1]; ++y)
            for (int x = 0; x < p.n[0]; ++x) {
                const std::uint32_t u = p.unpadded(x, y, z);
                lists[p.index(x, y, z)].assign(prims.begin() + offsets[u], prims.begin() + offsets[u + 1]);
            }
    return ic_image_lists(std::move(lists), shapes, allow_resident, layout);
}

} // namespace nesshi::kernels
