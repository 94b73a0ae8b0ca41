// Fuzz target `nff`: NFF scene text through the reader; a scene it accepts (up to a few hundred
// entities) is prepared (shapes, a 6^3 grid) and rendered natively at 6 x 6 on one thread.
// Bad input is a SceneError, never a crash.
#include "rt/render.hpp"
#include "rt/scene.hpp"

#include <cstdint>
#include <string_view>

using namespace nesshi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    rt::Scene scene;
    try {
        scene = rt::parse_nff(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.nff");
    } catch (const rt::SceneError&) {
        return 0;
    }
    if (scene.entities.size() > 300) return 0; // keep one input fast; the reader has seen it all
    const rt::PreparedScene prep = rt::prepare(std::move(scene), 6);
    rt::RenderOptions opt;
    opt.width = opt.height = 6;
    opt.threads = 1;
    opt.id_buffer = opt.t_buffer = true;
    (void)rt::render_native(prep, opt);
    return 0;
}
