// The paper's step costs (Gwun et al. 1993, PAPER.md): cycles of the machine's kernels as the
// authors measured them, and the ILP and utilisation ranges over their scenes. One place for every
// layer that prices work at the paper's figures: the grid pre-pass (rt), the kernel report
// (machine) and the gap analysis (paper). The published tables themselves are paper/published.hpp.
#pragma once

namespace nesshi::kernels {

struct PaperFigures {
    double dda_step_vliw = 11, dda_step_seq = 23; // one 3DDDA voxel step
    double dda_init = 60;                         // 3DDDA set-up of a ray
    double fifo_ray = 25;                         // receiving or sending a ray record (FIFO load/store)
    double triangle = 40, triangle_load = 10;     // ray/triangle test, and loading the shape
    double quadric = 50, quadric_load = 11;       // ray/quadric test, and loading the shape
    double os_ilp[2] = {2.27, 2.29}, os_util[2] = {0.56, 0.57};
    double ic_ilp[2] = {2.01, 2.31}, ic_util[2] = {0.50, 0.57};
};
inline constexpr PaperFigures kPaper{};

} // namespace nesshi::kernels
