// Dispatch policy: which intersection routine of the IC kernel a shape record selects (its
// CODE_* word), from the cheapest exact one its payload allows.
#pragma once

#include "kernels/abi.hpp"
#include "kernels/shape_record.hpp"

#include <cstddef>
#include <cstdint>

namespace nesshi::kernels {

// A quadric whose axis and length are zero (spheres) needs no axial clip: for any finite root
// h = a.q + s (a.d) is +-0, inside [0, 0]; for an infinite or NaN root the twin rejects it and so
// does the kernel (the root itself fails t > tmin or t < bound). Exact, and 16 operations fewer.
inline bool unclipped_quadric(const Shape& s) {
    return s.kind() == kShapeQuadric && s.w[13] == 0.0f && s.w[14] == 0.0f && s.w[15] == 0.0f && s.w[16] == 0.0f;
}

// A one-sided unclipped quadric with M = I, g = 0, J < 0 (a plain sphere): the twin's products by
// 1 and sums with +-0 are exact, so M d = d and M q + g/2 = q up to the sign of zero components,
// which cannot reach any result (a, b, c are sums with a non-zero term, or feed only b*b, -b +- r,
// c + J with J != 0). The kernel then skips 38 of the general form's operations.
inline bool plain_sphere(const Shape& s) {
    if (!unclipped_quadric(s) || s.two_sided()) return false;
    for (int i = 3; i < 6; ++i)
        if (s.w[static_cast<std::size_t>(i)] != 1.0f) return false;
    for (int i = 6; i < 12; ++i)
        if (s.w[static_cast<std::size_t>(i)] != 0.0f) return false;
    return s.w[12] < 0.0f;
}

inline std::uint32_t shape_code(const Shape& s) {
    const bool quad = s.kind() == kShapeQuadric;
    if (plain_sphere(s)) return static_cast<std::uint32_t>(abi::get("CODE_BALL1"));
    if (unclipped_quadric(s))
        return static_cast<std::uint32_t>(s.two_sided() ? abi::get("CODE_SPH2") : abi::get("CODE_SPH1"));
    return static_cast<std::uint32_t>(quad ? (s.two_sided() ? abi::get("CODE_QUAD2") : abi::get("CODE_QUAD1"))
                                           : (s.two_sided() ? abi::get("CODE_TRI2") : abi::get("CODE_TRI1")));
}

} // namespace nesshi::kernels
