// NFF reader: a token scanner with line/column positions and one small parser per entity.
#include "rt/scene.hpp"

#include "base/error.hpp"
#include "base/read_file.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <optional>

namespace nesshi::rt {

namespace {

struct Token {
    std::string_view text; // empty at end of input
    int line = 0, col = 0;
};

class Scanner {
public:
    Scanner(std::string_view text, std::shared_ptr<const std::string> file) : text_(text), file_(std::move(file)) {}

    Token peek() {
        if (!peeked_) peeked_ = scan();
        return *peeked_;
    }
    Token next() {
        Token t = peek();
        peeked_.reset();
        return t;
    }
    SourceLoc loc(const Token& t) const { return SourceLoc{file_, t.line, t.col}; }
    [[noreturn]] void fail(const Token& t, const std::string& msg) const { throw SceneError(loc(t), msg); }

    double number(const char* what) {
        Token t = next();
        if (t.text.empty()) fail(t, fmt::format("expected {} but the file ended", what));
        double v = 0;
        const char* b = t.text.data();
        const char* e = b + t.text.size();
        if (*b == '+') ++b;
        auto [p, ec] = std::from_chars(b, e, v);
        if (ec != std::errc() || p != e) fail(t, fmt::format("expected {} (a number), got '{}'", what, t.text));
        if (!std::isfinite(v)) fail(t, fmt::format("{} must be finite, got '{}'", what, t.text));
        if (std::abs(v) > 1e30) fail(t, fmt::format("{} is out of range (|x| <= 1e30), got '{}'", what, t.text));
        return v;
    }
    bool next_is_number() {
        Token t = peek();
        if (t.text.empty()) return false;
        char c = t.text[0];
        return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
    }
    Vec3d vec(const char* what) {
        Vec3d v;
        v.x = number(what);
        v.y = number(what);
        v.z = number(what);
        return v;
    }

private:
    Token scan() {
        for (;;) {
            while (pos_ < text_.size() && is_space(text_[pos_])) advance();
            if (pos_ < text_.size() && text_[pos_] == '#') {
                while (pos_ < text_.size() && text_[pos_] != '\n') advance();
                continue;
            }
            break;
        }
        Token t{{}, line_, col_};
        std::size_t start = pos_;
        while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '#') advance();
        t.text = text_.substr(start, pos_ - start);
        return t;
    }
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
    void advance() {
        if (text_[pos_] == '\n') {
            ++line_;
            col_ = 1;
        } else {
            ++col_;
        }
        ++pos_;
    }

    std::string_view text_;
    std::shared_ptr<const std::string> file_;
    std::size_t pos_ = 0;
    int line_ = 1, col_ = 1;
    std::optional<Token> peeked_;
};

Color color3(Scanner& s, const char* what) {
    Color c;
    c.r = static_cast<float>(s.number(what));
    c.g = static_cast<float>(s.number(what));
    c.b = static_cast<float>(s.number(what));
    return c;
}

int count_arg(Scanner& s, const char* what, int min, int max) {
    Token t = s.peek();
    double v = s.number(what);
    if (v != std::floor(v) || v < min || v > max)
        s.fail(t, fmt::format("{} must be an integer in [{}, {}], got '{}'", what, min, max, t.text));
    return static_cast<int>(v);
}

void parse_view(Scanner& s, Scene& sc, const Token& head) {
    View v;
    v.loc = s.loc(head);
    bool seen[6] = {};
    static constexpr std::string_view keys[6] = {"from", "at", "up", "angle", "hither", "resolution"};
    for (;;) {
        Token t = s.peek();
        int k = -1;
        for (int i = 0; i < 6; ++i)
            if (t.text == keys[i]) k = i;
        if (k < 0) break;
        s.next();
        if (seen[k]) s.fail(t, fmt::format("'{}' given twice in this view", t.text));
        seen[k] = true;
        switch (k) {
        case 0: v.from = s.vec("a 'from' coordinate"); break;
        case 1: v.at = s.vec("an 'at' coordinate"); break;
        case 2: v.up = s.vec("an 'up' coordinate"); break;
        case 3: {
            Token a = s.peek();
            v.angle = s.number("the view angle");
            if (!(v.angle > 0 && v.angle < 180)) s.fail(a, "the view angle must be in (0, 180) degrees");
            break;
        }
        case 4: v.hither = s.number("the hither distance"); break;
        case 5:
            v.width = count_arg(s, "the resolution width", 1, 1 << 16);
            v.height = count_arg(s, "the resolution height", 1, 1 << 16);
            break;
        }
    }
    for (int i = 0; i < 3; ++i)
        if (!seen[i]) s.fail(head, fmt::format("view has no '{}' line", keys[i]));
    Vec3d fwd = v.at - v.from;
    if (length(fwd) == 0) s.fail(head, "view 'from' and 'at' are the same point");
    if (length(cross(fwd, v.up)) <= 1e-12 * length(fwd) * length(v.up))
        s.fail(head, "view 'up' is zero or parallel to the viewing direction");
    sc.view = v;
}

int current_material(Scene& sc) {
    if (sc.materials.empty()) sc.materials.push_back(Material{}); // objects before any `f`: white diffuse
    return static_cast<int>(sc.materials.size()) - 1;
}

void parse_polygon(Scanner& s, Scene& sc, const Token& head, bool patch) {
    Entity e;
    e.kind = patch ? Entity::Kind::patch : Entity::Kind::polygon;
    e.loc = s.loc(head);
    e.material = current_material(sc);
    int n = count_arg(s, "the vertex count", 3, 1 << 20);
    for (int i = 0; i < n; ++i) {
        if (!s.next_is_number()) {
            Token t = s.peek();
            s.fail(t, fmt::format("polygon declares {} vertices but vertex {} is missing (found '{}')", n, i + 1,
                                  t.text.empty() ? "end of file" : std::string(t.text)));
        }
        e.verts.push_back(s.vec("a vertex coordinate"));
        if (patch) {
            Token nt = s.peek();
            Vec3d nv = s.vec("a vertex normal");
            if (length(nv) == 0) s.fail(nt, "patch vertex normal is zero");
            e.normals.push_back(normalize(nv));
        }
    }
    if (s.next_is_number())
        s.fail(s.peek(), fmt::format("polygon declares {} vertices but more numbers follow", n));
    Vec3d nrm = cross(e.verts[1] - e.verts[0], e.verts[2] - e.verts[1]);
    double scale = length(e.verts[1] - e.verts[0]) * length(e.verts[2] - e.verts[1]);
    if (!(length(nrm) > 1e-12 * scale) || scale == 0)
        s.fail(head, "degenerate polygon: its first three vertices are collinear or repeated");
    sc.entities.push_back(std::move(e));
}

} // namespace

Scene parse_nff(std::string_view text, const std::string& file) {
    Scanner s(text, std::make_shared<const std::string>(file));
    Scene sc;
    sc.name = file;
    bool have_view = false;
    for (;;) {
        Token t = s.next();
        if (t.text.empty()) break;
        if (t.text == "v") {
            parse_view(s, sc, t);
            have_view = true;
        } else if (t.text == "b") {
            sc.background = color3(s, "a background colour component");
        } else if (t.text == "l") {
            Light l;
            l.loc = s.loc(t);
            l.pos = s.vec("a light coordinate");
            if (s.next_is_number()) {
                l.color = color3(s, "a light colour component");
                l.has_color = true;
            }
            sc.lights.push_back(l);
        } else if (t.text == "f") {
            Material m;
            m.loc = s.loc(t);
            m.color = color3(s, "a material colour component");
            m.kd = s.number("Kd");
            m.ks = s.number("Ks");
            m.shine = s.number("the shine exponent");
            Token tt = s.peek();
            m.t = s.number("T (transmittance)");
            Token it = s.peek();
            m.ior = s.number("the index of refraction");
            if (m.t < 0 || m.t > 1) s.fail(tt, "T (transmittance) must be in [0, 1]");
            if (m.t > 0 && m.ior <= 0) s.fail(it, "the index of refraction must be positive");
            sc.materials.push_back(m);
        } else if (t.text == "s") {
            Entity e;
            e.kind = Entity::Kind::sphere;
            e.loc = s.loc(t);
            e.material = current_material(sc);
            e.base = s.vec("a sphere centre coordinate");
            Token rt = s.peek();
            e.base_r = s.number("the sphere radius");
            if (e.base_r == 0) s.fail(rt, "sphere radius is zero");
            sc.entities.push_back(std::move(e));
        } else if (t.text == "c") {
            Entity e;
            e.loc = s.loc(t);
            e.material = current_material(sc);
            e.base = s.vec("a cone base coordinate");
            Token br = s.peek();
            e.base_r = s.number("the cone base radius");
            e.apex = s.vec("a cone apex coordinate");
            Token ar = s.peek();
            e.apex_r = s.number("the cone apex radius");
            if (length(e.apex - e.base) == 0) s.fail(t, "cone base and apex are the same point");
            if (e.base_r == 0 && e.apex_r == 0) s.fail(br, "both cone radii are zero");
            if ((e.base_r < 0) != (e.apex_r < 0) && e.base_r != 0 && e.apex_r != 0)
                s.fail(ar, "cone radii must have the same sign");
            e.kind = std::abs(e.base_r) == std::abs(e.apex_r) ? Entity::Kind::cylinder : Entity::Kind::cone;
            sc.entities.push_back(std::move(e));
        } else if (t.text == "p") {
            parse_polygon(s, sc, t, false);
        } else if (t.text == "pp") {
            parse_polygon(s, sc, t, true);
        } else {
            s.fail(t, fmt::format("unknown entity '{}' (expected v, b, l, f, c, s, p or pp)", t.text));
        }
    }
    (void)have_view; // a file without a view keeps the default camera
    return sc;
}

Scene load_nff_file(const std::string& path) {
    std::string text;
    try {
        text = base::read_file(path);
    } catch (const base::Error& e) {
        throw SceneError(e.loc(), e.message());
    }
    return parse_nff(text, path);
}

} // namespace nesshi::rt
