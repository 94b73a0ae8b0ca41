// The FIFO messages of the kernel ABI (abi.hpp documents their words) as C++ records: the tag
// word, NEW (host -> OS), VISIT (OS -> IC) and HIT (IC -> SC).
#pragma once

#include "kernels/abi.hpp"

#include <array>
#include <bit>
#include <cstdint>

namespace nesshi::kernels::abi {

enum class Kind : std::uint32_t { eye = 0, shadow = 1, reflect = 2, refract = 3 };

struct Tag {
    std::uint32_t slot = 0;
    Kind kind = Kind::eye;
    std::uint32_t depth = 1;
    constexpr std::uint32_t word() const {
        return (slot & 0xffffu) | (static_cast<std::uint32_t>(kind) << 16) | ((depth & 63u) << 18);
    }
    static constexpr Tag from(std::uint32_t w) {
        return {w & 0xffffu, static_cast<Kind>((w >> 16) & 3u), (w >> 18) & 63u};
    }
};

inline std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }
inline float flt(std::uint32_t w) { return std::bit_cast<float>(w); }

// Host -> OS: a new ray.
struct NewRay {
    std::uint32_t tag = 0;
    float o[3] = {0, 0, 0}, d[3] = {0, 0, 1};
    float tmin = 0, tmax = 0;
    std::array<std::uint32_t, 9> words() const {
        return {tag, bits(o[0]), bits(o[1]), bits(o[2]), bits(d[0]), bits(d[1]), bits(d[2]), bits(tmin), bits(tmax)};
    }
};

// OS -> IC: the ray visits a non-empty voxel.
struct Visit {
    std::uint32_t tag = 0, voxel = 0;
    float t_in = 0, t_out = 0;
    float o[3] = {0, 0, 0}, d[3] = {0, 0, 0};
    float tmin = 0, tmax = 0;
    static Visit from(const std::uint32_t* w) {
        Visit v;
        v.tag = w[0];
        v.voxel = w[1];
        v.t_in = flt(w[2]);
        v.t_out = flt(w[3]);
        for (int k = 0; k < 3; ++k) {
            v.o[k] = flt(w[4 + k]);
            v.d[k] = flt(w[7 + k]);
        }
        v.tmin = flt(w[10]);
        v.tmax = flt(w[11]);
        return v;
    }
    std::array<std::uint32_t, 12> words() const {
        return {tag, voxel, bits(t_in), bits(t_out), bits(o[0]), bits(o[1]), bits(o[2]),
                bits(d[0]), bits(d[1]), bits(d[2]), bits(tmin), bits(tmax)};
    }
};

// IC -> SC: the nearest (or, for shadow rays, the first) hit in the voxel.
struct HitMsg {
    std::uint32_t tag = 0, shape = 0;
    float t = 0, u = 0, v = 0;
    std::uint32_t front = 0;
    static HitMsg from(const std::uint32_t* w) {
        return {w[0], w[1], flt(w[2]), flt(w[3]), flt(w[4]), w[5]};
    }
};

} // namespace nesshi::kernels::abi
