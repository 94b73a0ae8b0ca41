// Random inputs of the kernel report's synthetic workloads, public for tests that drive the
// kernels: a cubic occupancy grid, and shape records (a triangle with vertices in [-3, 3]^3, a
// unit sphere and a radius-1 cylinder along z, length 4, through a point near the origin).
#pragma once

#include "kernels/shape_record.hpp"
#include "kernels/twins/dda.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace nesshi::kbuild {

struct OccupancyGrid {
    kernels::twins::GridGeom g;
    std::vector<std::uint8_t> occ; // by voxel address, 1 = full
};
// An n^3 grid over [-10, 10]^3, each voxel full with probability `density`.
OccupancyGrid random_grid(int n, double density, std::mt19937& rng);

kernels::Shape random_triangle(std::mt19937& rng, bool two_sided);
kernels::Shape random_sphere(std::mt19937& rng, bool two_sided);
kernels::Shape random_cylinder(std::mt19937& rng); // one-sided

} // namespace nesshi::kbuild
