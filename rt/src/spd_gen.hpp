// Internal: the NFF writer and the generator entry points (one file per generator).
#pragma once
#include "base/vec.hpp"

#include <fmt/format.h>

#include <string>

namespace nesshi::rt {

using base::Vec3d;

// Writes NFF with numbers as %g (6 significant digits), like the SPD generators.
class NffWriter {
public:
    void background(double r, double g, double b) { out_ += fmt::format("b {:g} {:g} {:g}\n", r, g, b); }
    void view(Vec3d from, Vec3d at, Vec3d up, double angle, double hither, int res) {
        out_ += fmt::format("v\nfrom {:g} {:g} {:g}\nat {:g} {:g} {:g}\nup {:g} {:g} {:g}\nangle {:g}\nhither {:g}\n"
                            "resolution {} {}\n",
                            from.x, from.y, from.z, at.x, at.y, at.z, up.x, up.y, up.z, angle, hither, res, res);
    }
    void light(Vec3d p) { out_ += fmt::format("l {:g} {:g} {:g}\n", p.x, p.y, p.z); }
    void material(double r, double g, double b, double kd, double ks, double shine, double t, double ior) {
        out_ += fmt::format("f {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g}\n", r, g, b, kd, ks, shine, t, ior);
    }
    void sphere(Vec3d c, double r) { out_ += fmt::format("s {:g} {:g} {:g} {:g}\n", c.x, c.y, c.z, r); }
    void cone(Vec3d b, double br, Vec3d a, double ar) {
        out_ += fmt::format("c {:g} {:g} {:g} {:g} {:g} {:g} {:g} {:g}\n", b.x, b.y, b.z, br, a.x, a.y, a.z, ar);
    }
    template <class It>
    void polygon(It first, It last) {
        out_ += fmt::format("p {}\n", last - first);
        for (; first != last; ++first) out_ += fmt::format("{:g} {:g} {:g}\n", first->x, first->y, first->z);
    }
    const std::string& str() const { return out_; }

private:
    std::string out_;
};

void gen_balls(NffWriter& w, int size);
void gen_mount(NffWriter& w, int size);
void gen_rings(NffWriter& w, int size);
void gen_tetra(NffWriter& w, int size);
void gen_tree(NffWriter& w, int size);
void gen_gears(NffWriter& w, int size);

} // namespace nesshi::rt
