// Scene helpers: counts, bounding boxes, polygon triangulation and name-or-file loading.
#include "rt/scene.hpp"
#include "rt/spd.hpp"

#include "base/suggest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace nesshi::rt {

void Box::add(Vec3d p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}
void Box::add(const Box& b) {
    if (b.empty()) return;
    add(b.lo);
    add(b.hi);
}

SceneCounts count(const Scene& s) {
    SceneCounts c;
    for (const Entity& e : s.entities) {
        switch (e.kind) {
        case Entity::Kind::sphere: ++c.spheres; break;
        case Entity::Kind::cylinder: ++c.cylinders; break;
        case Entity::Kind::cone: ++c.cones; break;
        case Entity::Kind::polygon:
            ++c.polygons;
            c.triangles += e.verts.size() - 2;
            break;
        case Entity::Kind::patch:
            ++c.patches;
            c.triangles += e.verts.size() - 2;
            break;
        }
        const Material& m = s.materials[static_cast<std::size_t>(e.material)];
        if (m.ks > 0) ++c.reflective;
        if (m.t > 0) ++c.transmitting;
    }
    return c;
}

namespace {
Box disc_bounds(Vec3d c, Vec3d axis, double r) {
    r = std::abs(r);
    Vec3d ext;
    for (int i = 0; i < 3; ++i) ext[i] = r * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
    Box b;
    b.add(c - ext);
    b.add(c + ext);
    return b;
}
} // namespace

Box entity_bounds(const Entity& e) {
    Box b;
    switch (e.kind) {
    case Entity::Kind::sphere: {
        double r = std::abs(e.base_r);
        b.add(e.base - Vec3d{r, r, r});
        b.add(e.base + Vec3d{r, r, r});
        break;
    }
    case Entity::Kind::cylinder:
    case Entity::Kind::cone: {
        Vec3d axis = normalize(e.apex - e.base);
        b.add(disc_bounds(e.base, axis, e.base_r));
        b.add(disc_bounds(e.apex, axis, e.apex_r));
        break;
    }
    case Entity::Kind::polygon:
    case Entity::Kind::patch:
        for (Vec3d v : e.verts) b.add(v);
        break;
    }
    return b;
}

Box scene_bounds(const Scene& s) {
    Box b;
    for (const Entity& e : s.entities) b.add(entity_bounds(e));
    return b;
}

std::vector<std::array<int, 3>> triangulate(const std::vector<Vec3d>& v) {
    std::vector<std::array<int, 3>> out;
    const int n = static_cast<int>(v.size());
    if (n < 3) return out;
    Vec3d nrm = cross(v[1] - v[0], v[2] - v[1]);
    auto ccw = [&](int a, int b, int c) { return dot(cross(v[b] - v[a], v[c] - v[b]), nrm); };
    // Fast path: a convex polygon is a fan.
    bool convex = true;
    for (int i = 0; i < n && convex; ++i)
        if (ccw(i, (i + 1) % n, (i + 2) % n) < 0) convex = false;
    if (convex) {
        for (int i = 1; i + 1 < n; ++i)
            if (ccw(0, i, i + 1) > 0) out.push_back({0, i, i + 1});
        return out;
    }
    // Ear clipping: a corner is an ear when it is convex and no other remaining vertex lies inside it.
    std::vector<int> idx(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) idx[static_cast<std::size_t>(i)] = i;
    auto inside = [&](int p, int a, int b, int c) {
        return dot(cross(v[b] - v[a], v[p] - v[a]), nrm) >= 0 && dot(cross(v[c] - v[b], v[p] - v[b]), nrm) >= 0 &&
               dot(cross(v[a] - v[c], v[p] - v[c]), nrm) >= 0;
    };
    std::size_t guard = 0;
    std::size_t i = 0;
    while (idx.size() > 3 && guard < idx.size() * 2 + 4) {
        std::size_t m = idx.size();
        int a = idx[(i + m - 1) % m], b = idx[i % m], c = idx[(i + 1) % m];
        double turn = ccw(a, b, c);
        bool ear = turn > 0;
        for (std::size_t k = 0; ear && k < m; ++k) {
            int p = idx[k];
            if (p == a || p == b || p == c) continue;
            if (v[p] == v[a] || v[p] == v[b] || v[p] == v[c]) continue;
            if (inside(p, a, b, c)) ear = false;
        }
        if (turn == 0 && length(cross(v[b] - v[a], v[c] - v[b])) == 0) ear = true; // collinear: drop b, no triangle
        if (ear) {
            if (turn > 0) out.push_back({a, b, c});
            idx.erase(idx.begin() + static_cast<std::ptrdiff_t>(i % m));
            guard = 0;
            if (i >= idx.size()) i = 0;
        } else {
            i = (i + 1) % m;
            ++guard;
        }
    }
    if (idx.size() == 3 && ccw(idx[0], idx[1], idx[2]) > 0) out.push_back({idx[0], idx[1], idx[2]});
    // A self-intersecting outline can leave no ear; clip the rest as a fan rather than fail.
    if (idx.size() > 3)
        for (std::size_t k = 1; k + 1 < idx.size(); ++k)
            if (ccw(idx[0], idx[k], idx[k + 1]) > 0) out.push_back({idx[0], idx[k], idx[k + 1]});
    return out;
}

Scene load_scene(const std::string& file_or_name) {
    if (!std::filesystem::exists(file_or_name)) {
        std::optional<SpdName> spd;
        try {
            spd = parse_spd_name(file_or_name);
        } catch (const std::invalid_argument& e) {
            throw SceneError(SourceLoc(file_or_name), e.what());
        }
        if (spd) {
            std::string label = spd->size ? fmt::format("{}:{}", spd->name, spd->size) : spd->name;
            Scene s = parse_nff(generate_spd(spd->name, spd->size), label);
            s.name = label;
            return s;
        }
        // A bare name that is neither a file nor a built-in scene: say both, not just "cannot open"
        // (a path, with a folder or an extension, gets the system's reason from load_nff_file).
        if (file_or_name.find_first_of("/.") == std::string::npos) {
            std::vector<std::string> names = spd_names();
            names.push_back("gears");
            throw SceneError(SourceLoc(file_or_name),
                             fmt::format("unknown scene: no such file, and not a built-in one ({}, NAME:SIZE for another size){}",
                                         fmt::join(names, " "), base::did_you_mean(file_or_name.substr(0, file_or_name.find(':')), names)));
        }
    }
    return load_nff_file(file_or_name);
}

} // namespace nesshi::rt
