// Random shape records of the kernel report's synthetic workloads (also used by tests that drive
// the intersection kernels): a triangle with vertices in [-3, 3]^3, a unit sphere and a radius-1
// cylinder along z (length 4) through a point near the origin.
#pragma once

#include "kernels/shape_record.hpp"

#include <random>

namespace nesshi::machine {

kernels::Shape random_triangle(std::mt19937& rng, bool two_sided);
kernels::Shape random_sphere(std::mt19937& rng, bool two_sided);
kernels::Shape random_cylinder(std::mt19937& rng); // one-sided

} // namespace nesshi::machine
