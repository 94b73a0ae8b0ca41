// `nesshi render`: render a scene with a chosen model (native for now) to PNG, stats and buffers.
#include "commands.hpp"

#include "rt/render.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <functional>
#include <map>
#include <unistd.h>

namespace nesshi::cli {

namespace {

struct RenderArgs {
    std::string scene;
    std::string model = "native";
    std::string size = "512";
    std::string grid = "50";
    int threads = 0;
    std::string out, stats_json, id_buffer, t_buffer;
    double cutoff = 0;
    bool quiet = false;
};

// A model renders a prepared scene. Models S, M, V (the macropipeline host) register here later.
using ModelFn = std::function<rt::RenderResult(const rt::PreparedScene&, const rt::RenderOptions&)>;
const std::map<std::string, ModelFn>& models() {
    static const std::map<std::string, ModelFn> m = {
        {"native", [](const rt::PreparedScene& p, const rt::RenderOptions& o) { return rt::render_native(p, o); }},
    };
    return m;
}

int parse_int(const std::string& s, const char* what) {
    int v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v < 1)
        throw std::runtime_error(fmt::format("bad {} '{}'", what, s));
    return v;
}

void run_render(const RenderArgs& a) {
    auto mit = models().find(a.model);
    if (mit == models().end())
        throw std::runtime_error(fmt::format("unknown model '{}' (available: native)", a.model));
    rt::RenderOptions opt;
    if (auto x = a.size.find('x'); x != std::string::npos) {
        opt.width = parse_int(a.size.substr(0, x), "width");
        opt.height = parse_int(a.size.substr(x + 1), "height");
    } else {
        opt.width = opt.height = parse_int(a.size, "size");
    }
    if (opt.width > 16384 || opt.height > 16384) throw std::runtime_error("image size is limited to 16384");
    int grid = a.grid == "auto" ? 0 : parse_int(a.grid, "grid resolution");
    if (grid > 512) throw std::runtime_error("grid resolution is limited to 512");
    opt.threads = a.threads;
    opt.cutoff = a.cutoff;
    opt.id_buffer = !a.id_buffer.empty();
    opt.t_buffer = !a.t_buffer.empty();
    const bool tty = isatty(STDERR_FILENO) && !a.quiet;
    if (tty)
        opt.progress = [](int done, int total) {
            int pct = total ? done * 100 / total : 100;
            int bar = pct * 40 / 100;
            fmt::print(stderr, "\r[{:<40}] {:3}% ", std::string(static_cast<std::size_t>(bar), '#'), pct);
            if (done == total) fmt::print(stderr, "\n");
        };

    rt::PreparedScene prep = rt::prepare(rt::load_scene(a.scene), grid);
    rt::RenderResult r = mit->second(prep, opt);

    if (!a.out.empty()) rt::write_png(a.out, r.image);
    if (opt.id_buffer) rt::write_id_buffer(a.id_buffer, r.id_buffer);
    if (opt.t_buffer) rt::write_t_buffer(a.t_buffer, r.t_buffer);
    if (!a.stats_json.empty()) {
        std::ofstream f(a.stats_json);
        f << rt::stats_json(prep, opt, r, a.model);
        if (!f) throw std::runtime_error(fmt::format("{}: cannot write", a.stats_json));
    }
    if (!a.quiet) {
        fmt::print("{} {}x{} model {} (SPD mode: depth {}, corner rays{})\n", prep.scene.name, opt.width, opt.height,
                   a.model, opt.max_depth, opt.cutoff > 0 ? fmt::format(", cut-off {:g}", opt.cutoff) : "");
        fmt::print("{}", rt::format_grid(prep.grid, prep.shapes.shapes.size()));
        fmt::print("{}", rt::format_rays(r.stats));
    }
}

} // namespace

void add_render(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "Render a scene (NFF file or built-in SPD name) to PNG");
    auto a = std::make_shared<RenderArgs>();
    cmd->add_option("scene", a->scene, "NFF file or built-in name (balls mount rings tetra tree gears, NAME:SIZE)")->required();
    cmd->add_option("--model", a->model, "model: native (S, M, V come with the macropipeline host)");
    cmd->add_option("--size", a->size, "image size W or WxH (default 512)");
    cmd->add_option("--grid", a->grid, "voxels per axis, or 'auto' (default 50)");
    cmd->add_option("--threads", a->threads, "host threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("-o,--output", a->out, "PNG image");
    cmd->add_option("--stats-json", a->stats_json, "statistics as JSON");
    cmd->add_option("--id-buffer", a->id_buffer, "eye-ray primitive ids: raw int32 LE, (H+1) x (W+1)");
    cmd->add_option("--t-buffer", a->t_buffer, "eye-ray hit distances: raw float32 LE, (H+1) x (W+1)");
    cmd->add_option("--cutoff", a->cutoff, "contribution cut-off for secondary rays (0 = off, SPD mode)");
    cmd->add_flag("-q,--quiet", a->quiet, "no report, no progress bar");
    cmd->callback([a] {
        try {
            run_render(*a);
        } catch (const std::exception& e) {
            std::string msg = e.what();
            if (msg.find(": error: ") == std::string::npos) msg = "nesshi render: error: " + msg;
            fmt::print(stderr, "{}\n", msg);
            throw CLI::RuntimeError(1);
        }
    });
}

} // namespace nesshi::cli
