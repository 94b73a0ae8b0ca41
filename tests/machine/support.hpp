// Shared by the machine tests: small single-threaded renders on one model.
#pragma once

#include "machine/machine.hpp"
#include "rt/render.hpp"

#include <string>

// Where the machine tests' data files live (the build passes the folder).
inline const std::string kData = NESSHI_TEST_DATA;

namespace nesshi::machine::test {

inline rt::RenderOptions small(int size) {
    rt::RenderOptions o;
    o.width = o.height = size;
    o.threads = 1;
    o.id_buffer = o.t_buffer = true;
    return o;
}

inline Options model(Model m) {
    Options mo;
    mo.model = m;
    mo.threads = 1;
    return mo;
}

} // namespace nesshi::machine::test
