// Uniform grid over the scene's box, laid out as the OS and IC memories will hold it.
//
// OS SRAM: the voxel occupancy map, 1 byte per voxel (0 empty, 1 holds primitives), x fastest, then
// y, then z (address = (iz*ny + iy)*nx + ix), plus the grid geometry of twins/dda.hpp. The machine
// holds it with a one-voxel frame, (nx+2)(ny+2)(nz+2) bytes from 0x90000, after the geometry and
// the ray state table (kernels/abi.hpp): up to 112^3 voxels fit the OS's 2 MB.
// IC memory: per-voxel list offsets (nx*ny*nz + 1 words, uint32: the list of voxel v is
// prims[offsets[v] .. offsets[v+1])), the lists (uint32 shape indices, ascending), and the shape
// records (20 words each, shapes.hpp). IC has 1 MB resident memory + 1 MB cache over global memory;
// the machine's tables are over the padded grid (kernels/image.hpp).
#pragma once
#include "rt/shapes.hpp"
#include "kernels/twins/dda.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::rt {

inline constexpr std::size_t kOsSramBytes = 2u << 20;
inline constexpr std::size_t kIcResidentBytes = 1u << 20;
inline constexpr std::size_t kIcCacheBytes = 1u << 20;

struct GridStats {
    int n[3] = {0, 0, 0};
    std::size_t voxels = 0, empty_voxels = 0, references = 0;
    double refs_per_nonempty = 0;
    double build_seconds = 0;
};

// The machine's layout, from the capacity rules of kernels/abi.hpp that the machine applies too
// (os_sram_fits, ic_data_fit_resident): the report says "fits" exactly when the machine takes the
// grid, and "fits resident" exactly when it puts all IC data in resident memory.
struct MemoryFootprint {
    std::size_t os_voxel_map = 0;   // occupancy bytes, unpadded (nx ny nz)
    std::size_t os_padded_map = 0;  // the map as the OS holds it, with its frame: (nx+2)(ny+2)(nz+2)
    std::size_t os_below_map = 0;   // geometry and ray state table, below the map (OS_OCC)
    std::size_t os_used = 0;        // os_below_map + os_padded_map: the end of the map in OS SRAM
    bool os_sram_fits = false;      // kernels::abi::os_sram_fits
    std::size_t ic_header = 0;      // header and dispatch tables below IC_DATA
    std::size_t ic_offsets = 0;     // voxel table: a list address per padded voxel
    std::size_t ic_lists = 0;       // a word per reference, an END word per list, one read-ahead word
    std::size_t ic_shapes = 0;      // the END record and the shape records, 80 B each
    bool ic_data_resident = false;  // kernels::abi::ic_data_fit_resident
    std::size_t os_total() const { return os_used; }
    std::size_t ic_total() const { return ic_header + ic_offsets + ic_lists + ic_shapes; }
    bool os_fits() const { return os_sram_fits; }
    bool ic_resident_fits() const { return ic_data_resident; }
};

struct Grid {
    kernels::twins::GridGeom geom;
    Box box;                          // double copy of the grid box
    double pad = 0;                   // voxels are enlarged by this much in the overlap tests
    std::vector<std::uint8_t> occupancy;
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> prims;
    GridStats stats;

    std::size_t voxel_count() const { return occupancy.size(); }
    Box voxel_box(int ix, int iy, int iz) const; // unpadded
    MemoryFootprint footprint(std::size_t shape_count) const;
};

// A quick resolution rule: N = clamp(round(3 * cbrt(shapes)), 4, 100), about 27 voxels per primitive
// (build_grid uses it for N = 0). `nesshi render --grid auto` uses the pre-pass of render.hpp instead.
int auto_grid_resolution(std::size_t shape_count);
Grid build_grid(const Scene& scene, const ShapeSet& shapes, int n);

// Exact overlap tests used by the builder (double precision; exposed for the tests).
bool sphere_box_overlap(Vec3d c, double r, const Box& b);
bool triangle_box_overlap(const std::array<Vec3d, 3>& tri, const Box& b);
bool box_box_overlap(const Box& a, const Box& b);

} // namespace nesshi::rt
