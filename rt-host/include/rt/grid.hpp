// Uniform grid over the scene's box, laid out as the OS and IC memories will hold it.
//
// OS SRAM: the voxel occupancy map, 1 byte per voxel (0 empty, 1 holds primitives), x fastest, then
// y, then z (address = (iz*ny + iy)*nx + ix), plus the 16-word grid geometry of twins/dda.hpp.
// 100^3 voxels = 1,000,000 bytes, within the OS's 2 MB.
// IC memory: per-voxel list offsets (nx*ny*nz + 1 words, uint32: the list of voxel v is
// prims[offsets[v] .. offsets[v+1])), the lists (uint32 shape indices, ascending), and the shape
// records (20 words each, shapes.hpp). IC has 1 MB resident memory + 1 MB cache over global memory.
#pragma once
#include "rt/shapes.hpp"
#include "rt/twins/dda.hpp"

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

struct MemoryFootprint {
    std::size_t os_voxel_map = 0;   // occupancy bytes
    std::size_t os_geometry = 0;    // grid geometry words
    std::size_t ic_offsets = 0;
    std::size_t ic_lists = 0;
    std::size_t ic_shapes = 0;
    std::size_t os_total() const { return os_voxel_map + os_geometry; }
    std::size_t ic_total() const { return ic_offsets + ic_lists + ic_shapes; }
    bool os_fits() const { return os_total() <= kOsSramBytes; }
    bool ic_resident_fits() const { return ic_total() <= kIcResidentBytes; }
};

struct Grid {
    twins::GridGeom geom;
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
