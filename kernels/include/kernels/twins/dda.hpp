// Native twin of the OS 3DDDA kernel (Amanatides-Woo / Snyder-Barr): the assembly kernel mirrors it.
//
// The grid geometry below is what OS SRAM holds next to the voxel map (binary32 and int32 words).
// Setup (initial rays only), per axis k, in order x, y, z (binary32, no FMA; min(a,b) = a < b ? a : b,
// max(a,b) = a > b ? a : b; int() truncates toward zero):
//   inv = 1/d;  ta = (lo - o)*inv;  tb = (hi - o)*inv
//   near = min(ta, tb); far = max(ta, tb); if d == 0: near = inside ? -inf : +inf, far = -near
//       (inside: lo <= o && o <= hi)  -- selects, so 0*inf never reaches a result
//   t_in = max(max(max(tmin, near_x), near_y), near_z); t_exit = min(min(min(tmax, far_x), far_y), far_z)
//   no voxel when !(t_in <= t_exit)
//   p = o + t_in*d;  f = (p - lo)*inv_cell;  f = max(min(f, n - 1), 0);  i = int(f)
//   step = d > 0 ? 1 : -1;  end = d > 0 ? n : -1;  address step = step * (1, nx, nx*ny)
//   next = (lo + float(i + (d > 0)) * cell - o) * inv   (d == 0: +inf)
//   delta = cell * abs(inv)                              (d == 0: +inf)
//   address = (iz*ny + iy)*nx + ix
// Loop (one voxel step, the 11-cycle loop of the paper):
//   current voxel spans [t_in, min(min(min(next_x, next_y), next_z), t_exit)]
//   axis = next_x <= next_y && next_x <= next_z ? x : (next_y <= next_z ? y : z)
//   stop when next_axis > t_exit; i_axis += step; stop when i_axis == end
//   t_in = next_axis; next_axis += delta_axis; address += address step
#pragma once
#include "base/vec.hpp"

#include <cstdint>
#include <limits>

namespace nesshi::kernels::twins {

using base::Vec3;
using base::Vec3d;
using base::Vec3f;


struct GridGeom {
    Vec3f lo, hi;     // grid box
    Vec3f cell;       // voxel size per axis
    Vec3f inv_cell;   // 1 / cell
    int n[3] = {1, 1, 1};
};

// n^3 cubic voxels over [lo, lo + size]^3: the grid of the synthetic workloads and benchmarks.
inline GridGeom cubic_grid(int n, float lo, float size) {
    GridGeom g;
    for (int k = 0; k < 3; ++k) {
        g.n[k] = n;
        g.lo[k] = lo;
        g.cell[k] = size / static_cast<float>(n);
        g.hi[k] = lo + static_cast<float>(n) * g.cell[k];
        g.inv_cell[k] = 1.0f / g.cell[k];
    }
    return g;
}

struct DdaState {
    int i[3];
    int step[3];
    int end[3];
    int addr_step[3];
    int addr;
    float next[3];
    float delta[3];
    float t_in, t_exit;
    float voxel_exit() const {
        float m = next[0] < next[1] ? next[0] : next[1];
        m = m < next[2] ? m : next[2];
        return m < t_exit ? m : t_exit;
    }
};

inline float fmin2(float a, float b) { return a < b ? a : b; }
inline float fmax2(float a, float b) { return a > b ? a : b; }

// Returns false when the ray segment (tmin, tmax) misses the grid box.
inline bool dda_setup(const GridGeom& g, Vec3f o, Vec3f d, float tmin, float tmax, DdaState& s) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    float t_in = tmin, t_exit = tmax;
    float inv[3];
    for (int k = 0; k < 3; ++k) {
        const float dk = d[k], ok = o[k];
        inv[k] = 1.0f / dk;
        const float ta = (g.lo[k] - ok) * inv[k];
        const float tb = (g.hi[k] - ok) * inv[k];
        float near = fmin2(ta, tb), far = fmax2(ta, tb);
        const bool inside = g.lo[k] <= ok && ok <= g.hi[k];
        const bool zero = dk == 0.0f;
        near = zero ? (inside ? -inf : inf) : near;
        far = zero ? (inside ? inf : -inf) : far;
        t_in = fmax2(t_in, near);
        t_exit = fmin2(t_exit, far);
    }
    if (!(t_in <= t_exit)) return false;
    for (int k = 0; k < 3; ++k) {
        const float dk = d[k];
        const float p = o[k] + t_in * dk;
        float f = (p - g.lo[k]) * g.inv_cell[k];
        f = fmax2(fmin2(f, static_cast<float>(g.n[k] - 1)), 0.0f); // a NaN becomes n - 1
        const int i = static_cast<int>(f);
        const bool pos = dk > 0.0f;
        const bool zero = dk == 0.0f;
        s.i[k] = i;
        s.step[k] = pos ? 1 : -1;
        s.end[k] = pos ? g.n[k] : -1;
        const float boundary = g.lo[k] + static_cast<float>(i + (pos ? 1 : 0)) * g.cell[k];
        s.next[k] = zero ? inf : (boundary - o[k]) * inv[k];
        s.delta[k] = zero ? inf : g.cell[k] * (inv[k] < 0.0f ? -inv[k] : inv[k]);
    }
    s.addr_step[0] = s.step[0];
    s.addr_step[1] = s.step[1] * g.n[0];
    s.addr_step[2] = s.step[2] * (g.n[0] * g.n[1]);
    s.addr = (s.i[2] * g.n[1] + s.i[1]) * g.n[0] + s.i[0];
    s.t_in = t_in;
    s.t_exit = t_exit;
    return true;
}

// Advances to the next voxel; false when the ray leaves the grid or passes t_exit.
inline bool dda_step(DdaState& s) {
    const int k = (s.next[0] <= s.next[1] && s.next[0] <= s.next[2]) ? 0 : (s.next[1] <= s.next[2] ? 1 : 2);
    if (s.next[k] > s.t_exit) return false;
    s.i[k] += s.step[k];
    if (s.i[k] == s.end[k]) return false;
    s.t_in = s.next[k];
    s.next[k] += s.delta[k];
    s.addr += s.addr_step[k];
    return true;
}

} // namespace nesshi::kernels::twins
