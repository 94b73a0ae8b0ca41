// The native float32 renderer: Whitted shading with the SPD rules over the grid and the twins.
//
// A macropipeline host reuses the pieces: prepare() (scene -> shapes -> grid -> camera, timed apart),
// Camera::eye_ray (the distributor), nearest_hit/any_hit (OS + IC), the shading helpers in
// shading.hpp (SC), and RenderStats/stats_json for the report.
#pragma once
#include "rt/camera.hpp"
#include "rt/grid.hpp"
#include "rt/image.hpp"
#include "rt/scene.hpp"
#include "rt/shapes.hpp"
#include "rt/trace.hpp"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <functional>
#include <string>

namespace nesshi::rt {

inline constexpr float kSecondaryEpsilon = 1e-4f; // secondary and shadow rays ignore hits closer than this

struct RenderOptions {
    int width = 512, height = 512;
    int threads = 0;         // 0 = all hardware threads
    int max_depth = 5;       // SPD rule 7
    float epsilon = kSecondaryEpsilon;
    double cutoff = 0;       // the paper's contribution cut-off; 0 = off (SPD mode)
    bool id_buffer = false, t_buffer = false;
    bool brute_force = false; // test every shape for every ray (reference for the grid's ray counts)
    // Called from the calling thread about 10 times a second with (corner rows done, rows total).
    std::function<void(int, int)> progress;
};

struct RayStats {
    std::uint64_t eye_rays = 0, eye_rays_hit = 0, shadow_rays = 0, shadow_rays_blocked = 0;
    std::uint64_t reflection_rays = 0, refraction_rays = 0, secondary_rays_hit = 0;
    std::uint64_t total_internal_reflections = 0;
    RayStats& operator+=(const RayStats& o);
    bool operator==(const RayStats&) const = default;
};

struct RenderStats {
    RayStats rays;
    std::array<TraceCounters, kRayKinds> traversal{}; // by RayKind
    double setup_seconds = 0, trace_seconds = 0;
    int threads = 1;
    float epsilon = kSecondaryEpsilon;
};

struct PreparedScene {
    Scene scene;
    ShapeSet shapes;
    Grid grid;
    double setup_seconds = 0; // shapes + grid (SPD rule 12: preprocessing apart from tracing)
};

struct RenderResult {
    Image image;
    std::vector<std::int32_t> id_buffer; // (H+1) x (W+1), entity index or -1
    std::vector<float> t_buffer;         // (H+1) x (W+1), t along the unit eye ray or -1
    RenderStats stats;
};

// Builds shapes and grid (grid_n voxels per axis; 0 = automatic, choose_grid_resolution).
PreparedScene prepare(Scene scene, int grid_n);

// The paper's suggestion for choosing the grid: a low-resolution pre-pass. Renders 64 x 64 (SPD mode)
// with N = 20, 35, 50, 70, 100 and takes the N with the least modelled cost
// 11 x voxel steps + 40 x triangle tests + 50 x quadric tests (the paper's cycles per 3DDDA step and
// per intersection); a tie goes to the smaller N. Deterministic; costs five 64 x 64 renders.
struct GridChoice {
    int n = 0;
    std::vector<std::pair<int, double>> costs; // (N, modelled cycles) per candidate
};
GridChoice choose_grid_resolution(const Scene& scene, const ShapeSet& shapes);
RenderResult render_native(const PreparedScene& prep, const RenderOptions& opt);

// Stats JSON (the keys: docs/stats-json.md), as a value that the machine's report extends;
// `model` names the model that produced the result. stats_text writes any of them.
inline constexpr int kStatsSchema = 2; // "schema": raised when a key changes meaning or type
nlohmann::json stats_json(const PreparedScene& prep, const RenderOptions& opt, const RenderResult& r,
                          const std::string& model);
std::string stats_text(const nlohmann::json& stats); // indented, with a final newline
// Readable tables. `tracer`: the traversal counters and the trace time, the native tracer's own
// figures (a machine's run counts no voxel steps or tests).
struct RayTables {
    bool tracer = true;
};
std::string format_rays(const RenderStats& s, RayTables what = {});
std::string format_grid(const Grid& g);

} // namespace nesshi::rt
