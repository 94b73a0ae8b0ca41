// The IC's work on one scene, sampled before the run: the ray trees of a coarse raster of pixel
// corners, traced natively over the grid, each non-empty voxel a ray visits (until it stops) as
// the VISIT the OS would send, with that voxel's list. A render measures its IC kernel's
// candidates on it and keeps the fastest for the scene: lists of one or two shapes and lists of
// forty favour different kernels on the same machine.
//
//   const kbuild::SceneSample s = kbuild::sample_scene(prep, opt);   // or LazySceneSample, traced when asked
//   std::uint64_t busy = kbuild::sample_busy_cycles(prog, s);
#pragma once

#include "kernels/messages.hpp"
#include "kernels/shape_record.hpp"
#include "rt/render.hpp"

#include "iss/program.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace nesshi::kbuild {

struct SceneSample {
    std::vector<kernels::Shape> shapes;             // the shapes the lists name, in scene order
    std::vector<std::vector<std::uint32_t>> lists;  // each visited voxel's list (indices into shapes)
    std::vector<kernels::abi::Visit> visits;        // in trace order; voxel = index into lists
    std::size_t corners = 0;                        // pixel corners whose ray trees were traced
    // "2,345 visits by the rays of 289 pixel corners"
    std::string what() const;
};

// A scene's sample traced the first time a kernel choice asks for it: a preset's kernel, one
// candidate, never does (the trace costs tens of milliseconds on the SPD scenes).
class LazySceneSample {
  public:
    LazySceneSample(const rt::PreparedScene& prep, const rt::RenderOptions& opt) : prep_(&prep), opt_(&opt) {}
    const SceneSample& get() const;

  private:
    const rt::PreparedScene* prep_;
    const rt::RenderOptions* opt_;
    mutable std::optional<SceneSample> sample_;
};

// Corners on a raster of at most `raster` x `raster` over the image (every corner of a smaller
// image), each traced to opt.max_depth with its shadow rays, as the native renderer traces it.
SceneSample sample_scene(const rt::PreparedScene& prep, const rt::RenderOptions& opt, int raster = 17);

// Processing plus communication cycles of the IC kernel `prog` over the sample's visits, one at a
// time, on the sample's lists laid out as the kernel wants them (kernels::ic_image_lists).
std::uint64_t sample_busy_cycles(const std::shared_ptr<const iss::Program>& prog, const SceneSample& s);

} // namespace nesshi::kbuild
