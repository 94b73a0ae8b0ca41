// nesshi.scene() and nesshi.render(): a scene through the native tracer or the simulated machine
// (nesshi scene info, nesshi render), the image as a numpy array and the stats JSON as a dict.
#include "convert.hpp"

#include "machine/machine.hpp"
#include "machine/memory_report.hpp"
#include "rt/render.hpp"
#include "rt/scene.hpp"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <optional>
#include <variant>

namespace nesshi::python {
namespace {

struct PyScene {
    rt::Scene s;
};

// "balls", "balls:1", an NFF file, or NFF text (anything holding a newline).
PyScene load_text(const std::string& spec) {
    if (spec.find('\n') != std::string::npos) return {rt::parse_nff(spec, "<string>")};
    return {rt::load_scene(spec)};
}

// The same from a str or an os.PathLike (a file), as assemble() takes its source.
PyScene load(const py::object& spec) {
    if (py::isinstance(spec, py::module_::import("os").attr("PathLike"))) return load_text(path_arg(spec));
    if (!py::isinstance<py::str>(spec))
        throw py::type_error("a scene is a nesshi.Scene, a name, NFF text, or a file (str or os.PathLike), not " +
                             py::str(py::type::of(spec).attr("__name__")).cast<std::string>());
    return load_text(spec.cast<std::string>());
}

py::dict info(const PyScene& p) {
    const rt::Scene& s = p.s;
    const rt::SceneCounts c = rt::count(s);
    const rt::Box b = rt::scene_bounds(s);
    auto vec = [](const auto& v) { return py::make_tuple(v.x, v.y, v.z); };
    py::dict d;
    d["name"] = s.name;
    d["primitives"] = c.total();
    d["spheres"] = c.spheres;
    d["cylinders"] = c.cylinders;
    d["cones"] = c.cones;
    d["polygons"] = c.polygons;
    d["patches"] = c.patches;
    d["triangles"] = c.triangles;
    d["reflective"] = c.reflective;
    d["transmitting"] = c.transmitting;
    d["lights"] = s.lights.size();
    d["materials"] = s.materials.size();
    d["view"] = py::dict(py::arg("from") = vec(s.view.from), py::arg("at") = vec(s.view.at), py::arg("up") = vec(s.view.up),
                         py::arg("angle") = s.view.angle, py::arg("hither") = s.view.hither,
                         py::arg("resolution") = py::make_tuple(s.view.width, s.view.height));
    d["background"] = py::make_tuple(s.background.r, s.background.g, s.background.b);
    d["bounds"] = b.empty() ? py::object(py::none()) : py::object(py::make_tuple(vec(b.lo), vec(b.hi)));
    return d;
}

py::object image_array(const rt::Image& img) {
    const py::bytes raw(reinterpret_cast<const char*>(img.rgb.data()), img.rgb.size());
    py::object np;
    try {
        np = py::module_::import("numpy");
    } catch (const py::error_already_set&) {
        return raw; // no numpy: rows of RGB bytes, top row first
    }
    return np.attr("frombuffer")(raw, np.attr("uint8")).attr("reshape")(img.height, img.width, 3);
}

// The command line's ranges for its options (nesshi render --help), with its words.
template <typename T>
void check_range(const char* name, const std::optional<T>& v, T lo, T hi) {
    if (v && (*v < lo || *v > hi))
        throw py::value_error(fmt::format("{} must be {} between {} and {} (got {})", name,
                                          std::is_integral_v<T> ? "an integer" : "a number", lo, hi, *v));
}

using Size = std::variant<int, std::pair<int, int>>;
using Grid = std::variant<int, std::string>;

struct RenderArgs {
    std::string model;
    std::optional<Size> size;
    Grid grid;
    int threads;
    double cutoff;
    machine::Options mo;
    bool window_given, slots_given;
};

py::tuple render(const RenderArgs& a, const PyScene& scene_in) {
    const bool native = a.model == "native";
    machine::Options mo = a.mo;
    if (!native && !machine::parse_model(a.model, mo.model))
        throw py::value_error("unknown model '" + a.model + "' (native, S, M, V)");
    // Bounded FIFOs without a chosen window or ray slots: as many rays in flight as cannot fill one.
    if (mo.fifo_capacity > 0 && !a.window_given && !a.slots_given) mo.ray_slots = machine::deadlock_free_ray_slots(mo.fifo_capacity);
    rt::RenderOptions opt;
    opt.width = scene_in.s.view.width;
    opt.height = scene_in.s.view.height;
    if (a.size) {
        if (const int* n = std::get_if<int>(&*a.size)) opt.width = opt.height = *n;
        else std::tie(opt.width, opt.height) = std::get<std::pair<int, int>>(*a.size);
        if (opt.width < 1 || opt.height < 1 || opt.width > 16384 || opt.height > 16384)
            throw py::value_error(fmt::format("bad size {}x{} (size is N or (W, H), each an integer between 1 and 16384)",
                                              opt.width, opt.height));
    }
    int grid = 0;
    if (const int* n = std::get_if<int>(&a.grid)) {
        grid = *n;
        if (grid < 1) throw py::value_error(fmt::format("bad grid resolution {} (grid is 'auto' or an integer from 1)", grid));
    } else if (std::get<std::string>(a.grid) != "auto") {
        throw py::value_error("grid is 'auto' or an integer from 1, not '" + std::get<std::string>(a.grid) + "'");
    }
    rt::check_grid_resolution(grid);
    opt.threads = mo.threads = a.threads;
    opt.cutoff = a.cutoff;
    std::string stats;
    machine::Result mr;
    {
        py::gil_scoped_release unlocked;
        rt::PreparedScene prep = rt::prepare(scene_in.s, grid);
        if (native) {
            mr.render = rt::render_native(prep, opt);
            stats = rt::stats_text(machine::with_memory_report(rt::stats_json(prep, opt, mr.render, a.model), prep.grid,
                                                               prep.shapes.shapes.size()));
        } else {
            mr = machine::render(prep, opt, mo);
            stats = rt::stats_text(machine::stats_json(prep, opt, mo, mr));
        }
    }
    return py::make_tuple(image_array(mr.render.image), to_python_json_text(stats));
}

} // namespace

void bind_render(py::module_& m) {
    py::class_<PyScene>(m, "Scene", "A scene: a built-in SPD scene (NAME or NAME:SIZE), an NFF file or NFF text.")
        .def("info", &info, "Counts, lights, materials, view, background and bounds (nesshi scene info).")
        .def_property_readonly("name", [](const PyScene& p) { return p.s.name; }, "the scene's name ('balls:1')")
        .def("__repr__", [](const PyScene& p) { return "nesshi.scene('" + p.s.name + "')"; });
    m.def("scene", &load, py::arg("spec"), "A scene: 'balls', 'tetra:3', an NFF file (a str or a pathlib.Path), or NFF text.");
    m.def("render",
          [](const py::object& scene, const std::string& model, std::optional<Size> size, Grid grid, int threads,
             double cutoff, const py::object& os_machine, const py::object& ic_machine, const py::object& seq_machine,
             int pes, const std::string& balance, std::optional<uint64_t> epoch, std::optional<int> window,
             size_t fifo_capacity, std::optional<int> ray_slots, uint32_t fifo_latency, bool cache,
             std::optional<uint32_t> cache_size, std::optional<uint32_t> cache_ways, std::optional<uint32_t> cache_line,
             std::optional<uint32_t> miss_cycles, bool resident, std::optional<uint64_t> quantum, uint64_t max_cycles, bool checked,
             const std::string& kernels) {
              check_range("threads", std::optional<int>(threads), 0, 1024);
              check_range("cutoff", std::optional<double>(cutoff), 0.0, 1.0);
              check_range("pes", std::optional<int>(pes), 1, 64);
              check_range<uint64_t>("epoch", epoch, 1, 1000000000);
              check_range("window", window, 1, 1048576);
              check_range<size_t>("fifo_capacity", std::optional<size_t>(fifo_capacity), 0, 268435456);
              check_range("ray_slots", ray_slots, 1, 4096);
              check_range<uint32_t>("fifo_latency", std::optional<uint32_t>(fifo_latency), 0, 1000000);
              check_range<uint32_t>("cache_size", cache_size, 16, 1073741824);
              check_range<uint32_t>("cache_ways", cache_ways, 1, 1024);
              check_range<uint32_t>("cache_line", cache_line, 4, 4096);
              check_range<uint32_t>("miss_cycles", miss_cycles, 0, 1000000);
              check_range<uint64_t>("quantum", quantum, 1, 1000000);
              if (!cache && (cache_size || cache_ways || cache_line || miss_cycles || !resident))
                  throw py::value_error("cache_size, cache_ways, cache_line, miss_cycles and resident=False need cache=True "
                                        "(without it the IC cache is ideal: every access hits)");
              if (model == "native") { // the command's rule for its Machine options (a value other than the default)
                  const char* given = pes != 1 ? "pes" : balance != "interleaved" ? "balance" : epoch ? "epoch"
                                    : window ? "window" : fifo_capacity ? "fifo_capacity" : ray_slots ? "ray_slots"
                                    : fifo_latency ? "fifo_latency" : cache ? "cache" : quantum ? "quantum"
                                    : max_cycles ? "max_cycles" : checked ? "checked" : !kernels.empty() ? "kernels"
                                    : !os_machine.is_none() ? "os_machine" : !ic_machine.is_none() ? "ic_machine"
                                    : !seq_machine.is_none() ? "seq_machine" : nullptr;
                  if (given)
                      throw py::value_error(fmt::format("{} needs model S, M or V (the simulated machine); model native is "
                                                        "the C++ tracer", given));
              }
              if (epoch && balance != "dynamic") throw py::value_error("epoch needs balance='dynamic'");
              if (balance != "interleaved" && balance != "dynamic") throw py::value_error("balance is 'interleaved' or 'dynamic'");
              if (model == "S" && (fifo_latency || quantum))
                  throw py::value_error("fifo_latency and quantum have no effect on model S (one processor runs the three "
                                        "stages on one clock)");
              RenderArgs a{model, size, grid, threads, cutoff, {}, window.has_value(), ray_slots.has_value()};
              machine::Options& mo = a.mo;
              mo.os_machine = stage_machine(os_machine, "os");
              mo.ic_machine = stage_machine(ic_machine, "ic");
              mo.seq_machine = stage_machine(seq_machine, "seq");
              mo.pes = pes;
              mo.dynamic_balance = balance == "dynamic";
              if (epoch) mo.epoch = *epoch;
              if (window) mo.window = *window;
              mo.fifo_capacity = fifo_capacity;
              if (ray_slots) mo.ray_slots = *ray_slots;
              mo.fifo_latency = fifo_latency;
              mo.cache.enabled = cache;
              if (cache_size) mo.cache.bytes = *cache_size;
              if (cache_ways) mo.cache.ways = *cache_ways;
              if (cache_line) mo.cache.line = *cache_line;
              if (miss_cycles) mo.cache.miss_cycles = *miss_cycles;
              mo.resident = resident;
              if (quantum) mo.quantum = *quantum;
              mo.max_cycles = max_cycles;
              mo.checked = checked;
              mo.kernels_dir = kernels;
              const PyScene s = py::isinstance<PyScene>(scene) ? scene.cast<PyScene>() : load(scene);
              return render(a, s);
          },
          py::arg("scene"), py::arg("model") = "V", py::arg("size") = py::none(), py::arg("grid") = 50, py::arg("threads") = 0,
          py::arg("cutoff") = 0.0, py::arg("os_machine") = py::none(), py::arg("ic_machine") = py::none(),
          py::arg("seq_machine") = py::none(), py::arg("pes") = 1, py::arg("balance") = "interleaved",
          py::arg("epoch") = py::none(), py::arg("window") = py::none(), py::arg("fifo_capacity") = 0,
          py::arg("ray_slots") = py::none(), py::arg("fifo_latency") = 0, py::arg("cache") = false,
          py::arg("cache_size") = py::none(), py::arg("cache_ways") = py::none(), py::arg("cache_line") = py::none(),
          py::arg("miss_cycles") = py::none(), py::arg("resident") = true, py::arg("quantum") = py::none(),
          py::arg("max_cycles") = 0, py::arg("checked") = false, py::arg("kernels") = "",
          "Render a scene (a nesshi.Scene or what nesshi.scene takes) as nesshi render does: model 'native', 'S', 'M' or "
          "'V' (default here; the command's default is native); size N or (W, H) (default: the scene's); grid N or "
          "'auto'; machines as presets, TOML files or nesshi.Machine. The other keywords are the command's options "
          "with '_' for '-' and its ranges (pes, balance, epoch, window, fifo_capacity, ray_slots, fifo_latency, cache, "
          "cache_size, cache_ways, cache_line, miss_cycles, resident=False for --no-resident, quantum, max_cycles, "
          "checked, kernels). Returns (image, stats): image an H x W x 3 uint8 numpy array (bytes without numpy), stats "
          "the dict nesshi render --stats-json writes. The GIL is released while it runs.");
}

} // namespace nesshi::python
