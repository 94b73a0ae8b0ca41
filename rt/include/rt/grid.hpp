// Uniform grid over the scene's box: per voxel, whether it holds primitives and which.
//
// occupancy: 1 byte per voxel (0 empty, 1 holds primitives), x fastest, then y, then z
// (index = (iz*ny + iy)*nx + ix), with the grid geometry of kernels/twins/dda.hpp. offsets: nx*ny*nz + 1
// words, the list of voxel v is prims[offsets[v] .. offsets[v+1]) (shape indices, ascending). How the
// machine holds these in its memories is kernels/image.hpp's business (and machine/memory_report.hpp's).
#pragma once
#include "rt/shapes.hpp"
#include "kernels/twins/dda.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::rt {

struct GridStats {
    int n[3] = {0, 0, 0};
    std::size_t voxels = 0, empty_voxels = 0, references = 0;
    double refs_per_nonempty = 0;
    double build_seconds = 0;
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
};

// A quick resolution rule: N = clamp(round(3 * cbrt(shapes)), 4, 100), about 27 voxels per primitive
// (build_grid uses it for N = 0). `nesshi render --grid auto` uses the pre-pass of render.hpp instead.
int auto_grid_resolution(std::size_t shape_count);

// The largest grid the tools build, in voxels per axis: 512^3 is 134 M voxels, about 2 GB of grid
// arrays. Every command that takes a resolution checks it here (render, scene info), and so does
// build_grid.
inline constexpr int kMaxGridResolution = 512;
// Throws std::invalid_argument "grid resolution is limited to 512" when n > kMaxGridResolution.
void check_grid_resolution(int n);

// n voxels per axis (0: auto_grid_resolution). A scene whose extent on an axis vanishes next to
// its distance from the origin (a unit sphere at 1e30) gets that axis widened to a few binary32
// steps, so the cells stay positive and the box holds the scene in float coordinates.
Grid build_grid(const Scene& scene, const ShapeSet& shapes, int n);

// Exact overlap tests used by the builder (double precision; exposed for the tests).
bool sphere_box_overlap(Vec3d c, double r, const Box& b);
bool triangle_box_overlap(const std::array<Vec3d, 3>& tri, const Box& b);
bool box_box_overlap(const Box& a, const Box& b);

} // namespace nesshi::rt
