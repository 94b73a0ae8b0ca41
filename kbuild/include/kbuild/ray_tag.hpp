// The kind a ray's tag carries to the kernels (kernels/messages.hpp), for the renderer's ray kind.
#pragma once

#include "kernels/messages.hpp"
#include "rt/trace.hpp"

namespace nesshi::kbuild {

inline kernels::abi::Kind tag_kind(rt::RayKind k) {
    switch (k) {
    case rt::RayKind::eye: return kernels::abi::Kind::eye;
    case rt::RayKind::shadow: return kernels::abi::Kind::shadow;
    case rt::RayKind::reflection: return kernels::abi::Kind::reflect;
    case rt::RayKind::refraction: return kernels::abi::Kind::refract;
    }
    return kernels::abi::Kind::eye;
}

} // namespace nesshi::kbuild
