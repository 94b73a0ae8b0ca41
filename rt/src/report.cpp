// Render and grid reports: stats JSON and readable tables.
#include "rt/render.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <string>

namespace nesshi::rt {

namespace {
nlohmann::json grid_json(const Grid& g) {
    return {
        {"n", {g.stats.n[0], g.stats.n[1], g.stats.n[2]}},
        {"voxels", g.stats.voxels},
        {"empty_voxels", g.stats.empty_voxels},
        {"references", g.stats.references},
        {"refs_per_nonempty_voxel", g.stats.refs_per_nonempty},
        {"box", {{"lo", {g.box.lo.x, g.box.lo.y, g.box.lo.z}}, {"hi", {g.box.hi.x, g.box.hi.y, g.box.hi.z}}}}
    };
}

} // namespace

nlohmann::json stats_json(const PreparedScene& prep, const RenderOptions& opt, const RenderResult& r,
                          const std::string& model) {
    const RayStats& s = r.stats.rays;
    nlohmann::json j;
    j["schema"] = kStatsSchema;
    j["scene"] = prep.scene.name;
    j["size"] = {opt.width, opt.height};
    j["grid"] = grid_json(prep.grid);
    j["model"] = model;
    j["spd_mode"] = opt.cutoff <= 0;
    j["max_depth"] = opt.max_depth;
    j["epsilon"] = std::stod(fmt::format("{:g}", r.stats.epsilon)); // 1e-4, not 9.99999974e-05
    j["primitives"] = prep.scene.entities.size();
    j["shapes"] = prep.shapes.shapes.size();
    j["rays"] = {{"eye_rays", s.eye_rays},
                 {"eye_rays_hit", s.eye_rays_hit},
                 {"shadow_rays", s.shadow_rays},
                 {"shadow_rays_blocked", s.shadow_rays_blocked},
                 {"reflection_rays", s.reflection_rays},
                 {"refraction_rays", s.refraction_rays},
                 {"secondary_rays_hit", s.secondary_rays_hit},
                 {"total_internal_reflections", s.total_internal_reflections}};
    nlohmann::json trav = nlohmann::json::object();
    for (int k = 0; k < kRayKinds; ++k) {
        const TraceCounters& c = r.stats.traversal[static_cast<std::size_t>(k)];
        trav[ray_kind_name(static_cast<RayKind>(k))] = {{"rays", c.rays},
                                                         {"voxel_steps", c.voxel_steps},
                                                         {"nonempty_voxels", c.nonempty_voxels},
                                                         {"triangle_tests", c.triangle_tests},
                                                         {"quadric_tests", c.quadric_tests},
                                                         {"quadric_two_roots", c.quadric_two_roots}};
    }
    j["traversal"] = trav;
    // Host time, not a result: under "host", which digests and comparisons leave out.
    j["host"] = {{"grid_build_seconds", prep.grid.stats.build_seconds},
                 {"setup_seconds", r.stats.setup_seconds},
                 {"trace_seconds", r.stats.trace_seconds},
                 {"threads", r.stats.threads}};
    return j;
}

std::string stats_text(const nlohmann::json& stats) { return stats.dump(2) + "\n"; }

std::string format_rays(const RenderStats& st, RayTables what) {
    const RayStats& s = st.rays;
    std::string o;
    o += fmt::format("rays (SPD mode, epsilon {:g}):\n", st.epsilon);
    o += fmt::format("  eye rays            {:>12}   hit {:>12}\n", s.eye_rays, s.eye_rays_hit);
    o += fmt::format("  shadow rays         {:>12}   blocked {:>8}\n", s.shadow_rays, s.shadow_rays_blocked);
    o += fmt::format("  reflection rays     {:>12}\n", s.reflection_rays);
    o += fmt::format("  refraction rays     {:>12}   total internal reflections {}\n", s.refraction_rays,
                     s.total_internal_reflections);
    o += fmt::format("  secondary rays hit  {:>12}\n", s.secondary_rays_hit);
    if (!what.tracer) return o;
    o += "traversal      rays      voxel steps   non-empty      tri tests   quadric tests   two roots\n";
    for (int k = 0; k < kRayKinds; ++k) {
        const TraceCounters& c = st.traversal[static_cast<std::size_t>(k)];
        o += fmt::format("  {:<10} {:>10} {:>14} {:>11} {:>14} {:>15} {:>11}\n", ray_kind_name(static_cast<RayKind>(k)),
                         c.rays, c.voxel_steps, c.nonempty_voxels, c.triangle_tests, c.quadric_tests, c.quadric_two_roots);
    }
    o += fmt::format("time: setup {:.3f} s, trace {:.3f} s ({} threads)\n", st.setup_seconds, st.trace_seconds,
                     st.threads);
    return o;
}

std::string format_grid(const Grid& g) {
    std::string o;
    o += fmt::format("grid {}x{}x{}: {} voxels, {} empty ({:.1f}%), {} references, {:.2f} per non-empty voxel, "
                     "built in {:.3f} s\n",
                     g.stats.n[0], g.stats.n[1], g.stats.n[2], g.stats.voxels, g.stats.empty_voxels,
                     g.stats.voxels ? 100.0 * static_cast<double>(g.stats.empty_voxels) / static_cast<double>(g.stats.voxels) : 0.0,
                     g.stats.references, g.stats.refs_per_nonempty, g.stats.build_seconds);
    return o;
}

} // namespace nesshi::rt
