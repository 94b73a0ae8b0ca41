// The SC stage's cycle-cost model. SC is modelled, not simulated: its work is counted in
// operations of each class and priced with the `seq` machine's latencies (one op issues per
// cycle; an op of latency L costs L cycles, since a sequential shader waits on each result).
// FIFO words cost one communication cycle each, as a `recv`/`send` on `seq` does.
//
// The counts follow the C++ shading code (rt/shading.hpp) step by step; they are estimates of
// straightforward sequential code, stated here so that anyone can change them.
#pragma once

#include "kernels/abi.hpp"

#include <cstdint>

namespace nesshi::machine {

struct OpMix {
    std::uint32_t alu = 0, fadd = 0, fmul = 0, fdiv = 0, load = 0, store = 0, branch = 0;
    constexpr OpMix operator+(const OpMix& o) const {
        return {alu + o.alu, fadd + o.fadd, fmul + o.fmul, fdiv + o.fdiv, load + o.load, store + o.store,
                branch + o.branch};
    }
};

namespace sc_cost {
// Read the slot's bookkeeping record (pixel, node, light) and dispatch on the message.
inline constexpr OpMix kDispatch{.alu = 4, .load = 3, .branch = 2};
// A miss of an eye/secondary ray: store the background colour into the node.
inline constexpr OpMix kBackground{.load = 3, .store = 4};
// A shadow ray's fate: one flag stored, the node's outstanding count decremented.
inline constexpr OpMix kShadowFate{.alu = 2, .load = 1, .store = 2};
// Surface: material record (colour, kd, ks, shine, t, ior), hit point p = o + d t.
inline constexpr OpMix kSurface{.alu = 2, .fadd = 3, .fmul = 3, .load = 12, .branch = 1};
// Normals. Flat triangle: the stored plane normal. Patch: w0, interpolation, normalise.
// Quadric: q = p - c, gradient M q + g/2, normalise. Normalise = dot, sqrt, reciprocal, scale.
inline constexpr OpMix kNormalize{.fadd = 2, .fmul = 6, .fdiv = 2};
inline constexpr OpMix kFlatNormal{.load = 3};
inline constexpr OpMix kPatchNormal{.fadd = 8, .fmul = 9, .load = 9};
inline constexpr OpMix kQuadricNormal{.fadd = 12, .fmul = 9, .load = 12};
// Face the normal to the ray, ambient term, mirror direction for the highlights.
inline constexpr OpMix kFaceAmbient{.fadd = 5, .fmul = 10, .store = 3, .branch = 1};
inline constexpr OpMix kMirror{.fadd = 5, .fmul = 9};
// Per light: direction and distance (sqrt, reciprocal), n.l test, diffuse term, shadow ray
// record stored in the slot table.
inline constexpr OpMix kLight{.alu = 3, .fadd = 7, .fmul = 14, .fdiv = 2, .load = 6, .store = 12, .branch = 2};
// Specular term: r.l, pow(r.l, shine) as exp2(shine log2 x) by short polynomials, scale.
inline constexpr OpMix kSpecular{.fadd = 14, .fmul = 20, .store = 3, .branch = 1};
// Secondary rays: reflection (mirror of d about n, normalised) and refraction (Snell).
inline constexpr OpMix kReflection{.alu = 2, .fadd = 5, .fmul = 9, .fdiv = 2, .store = 10, .branch = 1};
inline constexpr OpMix kRefraction{.alu = 2, .fadd = 9, .fmul = 16, .fdiv = 4, .store = 10, .branch = 2};
// A finished corner: its ray tree combined (per traced ray: ambient + terms + children).
inline constexpr OpMix kCombinePerRay{.fadd = 6, .fmul = 6, .load = 8, .branch = 2};
inline constexpr OpMix kCombinePerLight{.fadd = 6, .load = 7, .branch = 1};
// Words: a NEW ray (kernels/abi.hpp), a pixel corner to COL (index, r, g, b; the host's, no kernel's).
inline constexpr std::uint32_t kNewRayWords = kernels::abi::get("MSG_NEW"), kColWords = 4;
} // namespace sc_cost

} // namespace nesshi::machine
