// Shared helpers for the nesshi_rt tests: reference files, sanitizer-scaled counts, random rays.
#pragma once
#include "rt/render.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <random>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define NESSHI_RT_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NESSHI_RT_SANITIZED 1
#endif
#endif

namespace nesshi::rt::test {

// Under ASan (a Debug build) the heavy property tests run with fewer samples.
inline int scaled(int n) {
#ifdef NESSHI_RT_SANITIZED
    return n / 10;
#else
    return n;
#endif
}

inline std::string shared_spd(const std::string& file) { return std::string(NESSHI_SHARED_DIR) + "/spd/" + file; }
inline bool have_shared() { return std::filesystem::exists(shared_spd("balls-s1.nff")); }
#define NESSHI_REQUIRE_SHARED()                                                                              \
    do {                                                                                                     \
        if (!::nesshi::rt::test::have_shared()) {                                                            \
            WARN("skipped: reference data not found at " NESSHI_SHARED_DIR "/spd (set NESSHI_SHARED_DIR)"); \
            return;                                                                                          \
        }                                                                                                    \
    } while (0)

// Small reference scenes used by the grid/traversal/render tests.
inline const std::vector<std::string>& small_scenes() {
    static const std::vector<std::string> s = {"balls-s2.nff", "mount-s3.nff", "rings-s2.nff", "tetra-s3.nff",
                                               "tree-s5.nff",  "teapot-s2.nff", "gears-s1.nff"};
    return s;
}

inline Vec3f random_unit(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    for (;;) {
        Vec3f v{n(rng), n(rng), n(rng)};
        float l = std::sqrt(dot(v, v));
        if (l > 1e-3f) return v * (1.0f / l);
    }
}

inline Vec3f random_in(std::mt19937& rng, const Box& b, double grow) {
    Vec3f p;
    for (int k = 0; k < 3; ++k) {
        double e = (b.hi[k] - b.lo[k]) * grow + 1e-3;
        std::uniform_real_distribution<double> u(b.lo[k] - e, b.hi[k] + e);
        p[k] = static_cast<float>(u(rng));
    }
    return p;
}

} // namespace nesshi::rt::test
