// The kernel ABI: FIFO messages, channel numbers and memory layouts shared by the assembly
// kernels (through kernels/abi.inc, generated from kConstants below) and the C++ host.
//
// Design in one paragraph. A ray travels as a *tag* word (slot, kind, depth, flags) plus only
// the words the receiving stage needs. Everything a stage needs only for itself stays in that
// stage's memory, keyed by the ray's slot: the OS keeps the 3DDDA state of a ray that is away at
// the IC in an SRAM state table, so a ray the IC returns is one FIFO word (its tag); the host/SC
// keeps pixel, weight and depth bookkeeping. Reason: the IC is the bottleneck stage (paper,
// Table 2), and every word it must receive and forward costs it issue slots; the OS has two
// integer units for the loads and stores and a 2 MB SRAM with room to spare.
//
// Messages (32-bit words, in FIFO order):
//   NEW    host -> OS  ch 0   9 words  tag, ox, oy, oz, dx, dy, dz, tmin, tmax
//   RETURN IC -> OS    ch 0   1 word   tag (TAG_RETURN set: a ray resuming traversal)
//   VISIT  OS -> IC    ch 1  12 words  tag|TAG_RETURN, voxel, t_in, t_out, o(3), d(3), tmin, tmax
//   MISS   OS -> SC    ch 2   1 word   tag (left the grid or passed t_exit: background / light visible)
//   HIT    IC -> SC    ch 2   6 words  tag, shape index, t, u, v, front
// MISS and HIT carry the tag with TAG_RETURN clear. HIT: the nearest hit of the voxel with
// tmin < t <= t_out and t < tmax, ties to the lower shape index (rt::nearest_hit's rule); shadow
// rays: the nearest with tmin < t < tmax (any such hit kills the ray, rt::any_hit). u, v: the
// triangle's weights of e1, e2 (0 for quadrics); front: 1 for triangles and front quadric roots.
// The OS's input channel 0 carries NEW and RETURN messages merged in arrival order by the host.
// Rays: o finite, tmin >= 0 finite, tmin <= tmax; each direction component is 0 or has
// |d| >= 2^-60 (the host flushes smaller ones to zero), so no 3DDDA value is ever NaN.
//
// OS SRAM (0x0, 2 MB):
//   0x000000  grid geometry (GEOM_* byte offsets below)
//   0x001000  ray state table, OS_SLOTS entries of OS_STATE_BYTES (ST_* byte offsets below)
//   0x090000  padded occupancy map: (nx+2)(ny+2)(nz+2) bytes, x fastest; OCC_EMPTY, OCC_FULL,
//             and OCC_BORDER in the one-voxel frame around the grid, so stepping out of the grid
//             is found by the same load that tests occupancy (no per-axis index/end compares).
//   The voxel id sent to the IC is the padded index (address - OS_OCC).
// IC memory (resident 0x00400000, 1 MB; global 0x10000000, cached; seq maps both):
//   IC_HEADER (= resident base): word 0 address of the voxel table, word 1 address of the END
//   record; IC_JUMPS_A/B: the kernel's dispatch tables (IC_JUMPS_L: a hybrid kernel's loops). The
//   host places the records, table and lists from IC_DATA (all resident when they fit; else the
//   most-referenced records resident and the rest in global memory: kernels/image.hpp).
//   voxel table: one word per padded voxel: the byte address of its list. A list is the byte
//   addresses of its shape records, ascending by shape index, closed by the END record's
//   address (so the kernel needs no count and no end compare: END dispatches to `done`); a
//   kernel of per-kind loops wants them kind by kind, a hybrid one its long lists kind by kind
//   after the LOOPS record's address (kernels/image.hpp's ListLayout).
//   Shape record (20 words): rt/shapes.hpp's record, except word 0 = dispatch code (CODE_*,
//   a byte offset into the dispatch table) and word 19 (unused payload) = the shape index.
#pragma once

#include "base/vec.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace nesshi::kernels::abi {

struct Constant {
    std::string_view name;
    std::int64_t value;
    std::string_view comment;
};

// The single source of truth; abi.inc is generated from it (see inc_text()).
inline constexpr std::array kConstants = {
    // FIFO channels
    Constant{"CH_IN", 0, "every processor's input channel"},
    Constant{"CH_OS_IC", 1, "OS -> IC: VISIT"},
    Constant{"CH_OS_SC", 2, "OS -> SC: MISS"},
    Constant{"CH_IC_OS", 1, "IC -> OS: RETURN"},
    Constant{"CH_IC_SC", 2, "IC -> SC: HIT"},
    // tag word
    Constant{"TAG_SLOT_MASK", 0xffff, "bits 0..15: ray slot"},
    Constant{"TAG_KIND_SHIFT", 16, "bits 16..17: ray kind"},
    Constant{"TAG_KIND_MASK", 3, ""},
    Constant{"TAG_DEPTH_SHIFT", 18, "bits 18..23: depth"},
    Constant{"TAG_RETURN", 0x80000000, "bit 31: set by the OS on VISIT, so an echoed tag is a RETURN"},
    Constant{"KIND_EYE", 0, ""},
    Constant{"KIND_SHADOW", 1, ""},
    Constant{"KIND_REFLECT", 2, ""},
    Constant{"KIND_REFRACT", 3, ""},
    // message lengths (words)
    Constant{"MSG_NEW", 9, "tag o d tmin tmax"},
    Constant{"MSG_RETURN", 1, "tag"},
    Constant{"MSG_VISIT", 12, "tag voxel t_in t_out o d tmin tmax"},
    Constant{"MSG_MISS", 1, "tag"},
    Constant{"MSG_HIT", 6, "tag shape t u v front"},
    // OS SRAM
    Constant{"OS_GEOM", 0x0, "grid geometry"},
    Constant{"GEOM_LO", 0, "3 floats"},
    Constant{"GEOM_HI", 12, "3 floats"},
    Constant{"GEOM_CELL", 24, "3 floats"},
    Constant{"GEOM_INV_CELL", 36, "3 floats"},
    Constant{"GEOM_NMAX", 48, "3 floats: float(n - 1)"},
    Constant{"GEOM_N", 60, "3 ints"},
    Constant{"GEOM_STRIDE", 72, "3 ints: padded map strides 1, nx+2, (nx+2)(ny+2)"},
    Constant{"GEOM_OCC0", 84, "int: address of voxel (0,0,0) in the padded map"},
    Constant{"GEOM_BYTES", 88, ""},
    Constant{"OS_STATE", 0x1000, "ray state table"},
    Constant{"OS_STATE_SHIFT", 7, "entry = OS_STATE + (slot << 7)"},
    Constant{"OS_STATE_BYTES", 128, ""},
    Constant{"OS_SLOTS", 4096, "ray slots (in-flight rays)"},
    Constant{"ST_O", 0, "3 floats"},
    Constant{"ST_D", 12, "3 floats"},
    Constant{"ST_TMIN", 24, ""},
    Constant{"ST_TMAX", 28, ""},
    Constant{"ST_TEXIT", 32, ""},
    Constant{"ST_DELTA", 36, "3 floats"},
    Constant{"ST_ASTEP", 48, "3 ints: signed padded-map address steps"},
    Constant{"ST_NEXT", 60, "3 floats"},
    Constant{"ST_ADDR", 72, "int: map address of the current voxel"},
    Constant{"ST_TIN", 76, "float: entry t of the current voxel"},
    Constant{"OS_OCC", 0x90000, "padded occupancy map"},
    Constant{"OS_OCC_LIMIT", 0x200000, "end of SRAM"},
    Constant{"OCC_EMPTY", 0, ""},
    Constant{"OCC_FULL", 1, ""},
    Constant{"OCC_BORDER", 2, ""},
    // IC memory
    Constant{"IC_HEADER", 0x400000, "resident base"},
    Constant{"ICH_VOXTAB", 0, "word: address of the voxel table"},
    Constant{"ICH_END_REC", 4, "word: address of the END record"},
    Constant{"IC_JUMPS_A", 0x400040, "8 words: the kernel's dispatch table A (written by the kernel)"},
    Constant{"IC_JUMPS_B", 0x400060, "8 words: dispatch table B"},
    Constant{"IC_JUMPS_L", 0x400084, "8 words: a hybrid kernel's table of its loops (A + CODE_LOOPS is its entry)"},
    Constant{"IC_DATA", 0x400100, "first byte the host may use in resident memory"},
    Constant{"IC_RESIDENT_LIMIT", 0x500000, ""},
    Constant{"IC_GLOBAL", 0x10000000, ""},
    Constant{"REC_CODE", 0, "shape record word 0: dispatch code (CODE_*)"},
    Constant{"REC_ENTITY", 4, "NFF entity index"},
    Constant{"REC_W", 8, "payload w[0] (byte offset)"},
    Constant{"REC_INDEX", 76, "shape index (word 19)"},
    Constant{"REC_BYTES", 80, ""},
    Constant{"CODE_TRI1", 0, "one-sided triangle"},
    Constant{"CODE_TRI2", 4, "two-sided triangle"},
    Constant{"CODE_QUAD1", 8, "one-sided quadric"},
    Constant{"CODE_QUAD2", 12, "two-sided quadric"},
    Constant{"CODE_END", 16, "end of a voxel list"},
    Constant{"CODE_SPH1", 20, "one-sided quadric without axis clip (a = 0, L = 0: spheres)"},
    Constant{"CODE_SPH2", 24, "two-sided quadric without axis clip"},
    Constant{"CODE_BALL1", 28, "one-sided unit-matrix sphere: A=B=C=1, D..I=0, J<0, no clip"},
    Constant{"CODE_LOOPS", 64, "first entry of a long list for a hybrid kernel (kind by kind after it): past table B"},
};

// The value of an ABI constant, looked up at compile time: an unknown name is not a constant
// expression, so a typo fails to build (tests/kernels/abi_probe.cpp checks that it does).
consteval std::int64_t get(std::string_view name) {
    for (const auto& c : kConstants)
        if (c.name == name) return c.value;
    throw "unknown kernel ABI constant";
}

inline constexpr std::uint32_t kChIn = get("CH_IN");
inline constexpr std::uint32_t kChOsIc = get("CH_OS_IC");
inline constexpr std::uint32_t kChOsSc = get("CH_OS_SC");
inline constexpr std::uint32_t kChIcOs = get("CH_IC_OS");
inline constexpr std::uint32_t kChIcSc = get("CH_IC_SC");
inline constexpr std::uint32_t kTagReturn = static_cast<std::uint32_t>(get("TAG_RETURN"));
inline constexpr std::uint32_t kOsGeom = get("OS_GEOM");
inline constexpr std::uint32_t kOsState = get("OS_STATE");
inline constexpr std::uint32_t kOsStateBytes = get("OS_STATE_BYTES");
inline constexpr std::uint32_t kOsSlots = get("OS_SLOTS");
inline constexpr std::uint32_t kOsOcc = get("OS_OCC");
inline constexpr std::uint32_t kOsOccLimit = get("OS_OCC_LIMIT");
inline constexpr std::uint8_t kOccEmpty = 0, kOccFull = 1, kOccBorder = 2;
inline constexpr std::uint32_t kIcHeader = get("IC_HEADER");
inline constexpr std::uint32_t kIcData = get("IC_DATA");
inline constexpr std::uint32_t kIcGlobal = get("IC_GLOBAL");
inline constexpr std::uint32_t kRecBytes = get("REC_BYTES");
inline constexpr std::uint32_t kIcJumpsA = get("IC_JUMPS_A");
inline constexpr std::uint32_t kIcJumpsB = get("IC_JUMPS_B");
// An IC kernel that defines this label wants each voxel list laid out kind by kind (stably, by
// dispatch code): its per-kind loops read ahead of the list, so the last list is followed by
// kListReadAhead END entries (more than any loop's speculation depth).
inline constexpr const char* kListsByKindLabel = "lists_by_kind";
inline constexpr std::uint32_t kListReadAhead = 64;
// A hybrid IC kernel (the dispatch bodies for short lists, the per-kind loops for long ones)
// defines a label "lists_long_N": a list of at least N references starts with the LOOPS record
// (code CODE_LOOPS, beside the END record) and is laid out kind by kind after it; a
// shorter one stays in shape order. The last list is followed by kListReadAhead END entries.
inline constexpr std::string_view kListsLongPrefix = "lists_long_";
static_assert(get("OS_STATE") + get("OS_SLOTS") * get("OS_STATE_BYTES") <= get("OS_OCC"));
// Table A's LOOPS slot lies between table B and table L, all below the host's data.
static_assert(get("IC_JUMPS_A") + get("CODE_LOOPS") >= get("IC_JUMPS_B") + 32 &&
              get("IC_JUMPS_A") + get("CODE_LOOPS") + 4 <= get("IC_JUMPS_L") && get("IC_JUMPS_L") + 32 <= get("IC_DATA"));

// OS SRAM capacity, the one rule for it: the machine (machine::render, os_image
// in image.hpp) and the memory report (machine::memory_report, `nesshi scene info`, the stats JSON's
// os_fits) all call these, so they cannot disagree. A grid of nx x ny x nz voxels needs the
// OS_OCC bytes below the map (geometry, ray state table) plus the padded occupancy map,
// (nx+2)(ny+2)(nz+2) bytes: 112^3 fits, 113^3 does not. 64-bit, so no grid size wraps around.
constexpr std::uint64_t os_padded_map_bytes(int nx, int ny, int nz) {
    return static_cast<std::uint64_t>(nx + 2) * static_cast<std::uint64_t>(ny + 2) * static_cast<std::uint64_t>(nz + 2);
}
constexpr std::uint64_t os_sram_bytes(int nx, int ny, int nz) {
    return static_cast<std::uint64_t>(get("OS_OCC")) + os_padded_map_bytes(nx, ny, nz);
}
constexpr bool os_sram_fits(int nx, int ny, int nz) {
    return os_sram_bytes(nx, ny, nz) <= static_cast<std::uint64_t>(get("OS_OCC_LIMIT"));
}
static_assert(os_sram_fits(112, 112, 112) && !os_sram_fits(113, 113, 113));

// IC resident memory, the one rule for it (image.hpp's placement and machine::memory_report use it):
// the bytes the host places from IC_DATA for `shapes` shape records, `padded_voxels` voxel lists
// and `references` list entries: the END record and the shape records (REC_BYTES each), the
// voxel table (a word per padded voxel), the lists (a word per reference and an END word per
// list) and one read-ahead word. All of it goes to resident memory when it fits.
constexpr std::uint64_t ic_records_bytes(std::uint64_t shapes) {
    return (shapes + 1) * static_cast<std::uint64_t>(get("REC_BYTES"));
}
constexpr std::uint64_t ic_table_bytes(std::uint64_t padded_voxels) { return padded_voxels * 4; }
constexpr std::uint64_t ic_lists_bytes(std::uint64_t padded_voxels, std::uint64_t references) {
    return (references + padded_voxels) * 4 + 4;
}
constexpr std::uint64_t ic_data_bytes(std::uint64_t shapes, std::uint64_t padded_voxels, std::uint64_t references) {
    return ic_records_bytes(shapes) + ic_table_bytes(padded_voxels) + ic_lists_bytes(padded_voxels, references);
}
constexpr bool ic_data_fit_resident(std::uint64_t shapes, std::uint64_t padded_voxels, std::uint64_t references) {
    return static_cast<std::uint64_t>(get("IC_DATA")) + ic_data_bytes(shapes, padded_voxels, references) <=
           static_cast<std::uint64_t>(get("IC_RESIDENT_LIMIT"));
}
static_assert(get("OS_STATE_BYTES") == (1 << get("OS_STATE_SHIFT")));
static_assert(get("ST_TIN") + 4 <= get("OS_STATE_BYTES"));

// The text of kernels/abi.inc (checked in; a unit test keeps the file equal to this).
inline std::string inc_text() {
    std::string s = "# Kernel ABI constants. GENERATED from kernels/abi.hpp (kConstants): do not edit;\n"
                    "# tests/kernels/abi_test.cpp prints the new text when the two differ.\n";
    for (const auto& c : kConstants) {
        std::string line = ".equ " + std::string(c.name) + ", ";
        const auto v = static_cast<std::uint64_t>(c.value);
        if (c.value >= 4096) {
            static constexpr char hex[] = "0123456789abcdef";
            std::string h;
            for (std::uint64_t x = v; x != 0; x >>= 4) h.insert(h.begin(), hex[x & 15]);
            line += "0x" + h;
        } else {
            line += std::to_string(c.value);
        }
        if (!c.comment.empty()) line += "    # " + std::string(c.comment);
        s += line + "\n";
    }
    return s;
}

// The rule for ray directions above: a component below 2^-60 in magnitude is flushed to zero.
// Every ray the host makes, of every model, goes through it.
inline base::Vec3f flush_direction(base::Vec3f d) {
    for (int k = 0; k < 3; ++k)
        if (std::fabs(d[k]) < 0x1p-60f) d[k] = 0.0f;
    return d;
}

} // namespace nesshi::kernels::abi
