// nesshi.machine() and nesshi.Machine: a description's slots, ports, latencies and memories.
#include "convert.hpp"

#include <pybind11/stl.h>

namespace nesshi::python {
namespace {

// A Python-side machine: the description and the TOML text it was made from, if any.
struct PyMachine {
    isa::Machine m;
    std::string toml;     // the text it was parsed from ("" for presets and files)
};

bool looks_like_toml(const std::string& s) { return s.find('\n') != std::string::npos || s.find('=') != std::string::npos; }

PyMachine make_machine(const std::string& spec, const std::string& toml) {
    if (!toml.empty() || looks_like_toml(spec)) {
        const std::string& text = toml.empty() ? spec : toml;
        return {isa::parse_machine(text, "<string>"), text};
    }
    return {isa::load_machine(spec), ""};
}

py::dict latencies(const isa::Machine& m) {
    py::dict d;
    for (int c = 0; c < isa::kNumOpClasses; ++c) d[py::str(std::string(isa::kOpClassNames[c]))] = m.latency[c];
    return d;
}

py::list slots(const isa::Machine& m) {
    py::list out;
    for (const isa::SlotDesc& s : m.slots) {
        py::list accepts;
        for (int c = 0; c < isa::kNumOpClasses; ++c)
            if (s.accepts(static_cast<isa::OpClass>(c))) accepts.append(std::string(isa::kOpClassNames[c]));
        out.append(py::dict(py::arg("name") = s.name, py::arg("accepts") = accepts));
    }
    return out;
}

py::dict registers(const isa::Machine& m) {
    py::dict d;
    const char* names[isa::kNumRegFiles] = {"int", "float"}; // the TOML's [registers.int], [registers.float]
    for (int f = 0; f < isa::kNumRegFiles; ++f)
        d[names[f]] = py::dict(py::arg("count") = m.regs[f].count, py::arg("read_ports") = m.regs[f].read_ports,
                               py::arg("write_ports") = m.regs[f].write_ports);
    return d;
}

py::list memories(const isa::Machine& m) {
    py::list out;
    for (const isa::MemoryDesc& r : m.memories)
        out.append(py::dict(py::arg("name") = r.name, py::arg("base") = r.base, py::arg("size") = r.size,
                            py::arg("latency") = r.latency, py::arg("cached") = r.cached));
    return out;
}

} // namespace

isa::Machine machine_arg(const py::handle& arg, const std::string& fallback) {
    if (arg.is_none()) return isa::load_machine(fallback);
    if (py::isinstance<PyMachine>(arg)) return arg.cast<const PyMachine&>().m;
    return make_machine(py::str(arg).cast<std::string>(), "").m;
}

kbuild::StageMachine stage_machine(const py::handle& arg, const char* preset) {
    if (arg.is_none()) return kbuild::StageMachine(preset);
    if (py::isinstance<PyMachine>(arg)) {
        const PyMachine& pm = arg.cast<const PyMachine&>();
        return kbuild::StageMachine(pm.m, pm.toml.empty() ? pm.m.reference() : pm.m.name);
    }
    const std::string spec = py::str(arg).cast<std::string>();
    PyMachine pm = make_machine(spec, "");
    return kbuild::StageMachine(std::move(pm.m), pm.toml.empty() ? spec : pm.m.name);
}

void bind_machine(py::module_& m) {
    py::class_<PyMachine>(m, "Machine", "A machine description (a preset, a TOML file or TOML text): issue slots, "
                                         "latencies, register files and memories.")
        .def_property_readonly("name", [](const PyMachine& p) { return p.m.name; }, "the description's name")
        .def_property_readonly("description", [](const PyMachine& p) { return p.m.description; }, "one line on what it is")
        .def_property_readonly("source", [](const PyMachine& p) { return p.m.source; }, "\"builtin:os\", the file, or \"<string>\"")
        .def_property_readonly("slots", [](const PyMachine& p) { return slots(p.m); },
                               "[{'name': 'iu0', 'accepts': ['alu', ...]}, ...] in issue order")
        .def_property_readonly("latency", [](const PyMachine& p) { return latencies(p.m); }, "cycles by operation class")
        .def_property_readonly("registers", [](const PyMachine& p) { return registers(p.m); },
                               "{'int': {'count', 'read_ports', 'write_ports'}, 'float': {...}}")
        .def_property_readonly("memories", [](const PyMachine& p) { return memories(p.m); },
                               "[{'name', 'base', 'size', 'latency' (extra stall cycles), 'cached'}, ...]")
        .def_property_readonly("branch_penalty", [](const PyMachine& p) { return p.m.branch_penalty; },
                               "extra cycles after a taken branch")
        .def_property_readonly("fingerprint", [](const PyMachine& p) { return p.m.fingerprint(); },
                               "hash of everything that affects assembly or timing, and the name")
        .def("same_as", [](const PyMachine& a, const PyMachine& b) { return a.m.same_as(b.m); },
             "the same machine under any name (a file that only inherits a preset is that preset)")
        .def("__eq__", [](const PyMachine& a, const PyMachine& b) { return a.m.fingerprint() == b.m.fingerprint(); },
             py::is_operator()) // another type: NotImplemented, so `m == 5` is False and `m in [None]` works
        .def("__hash__", [](const PyMachine& p) { return p.m.fingerprint(); })
        .def(py::pickle([](const PyMachine& p) { return py::make_tuple(p.toml.empty() ? p.m.reference() : "", p.toml); },
                        [](const py::tuple& t) { return make_machine(t[0].cast<std::string>(), t[1].cast<std::string>()); }))
        .def("__repr__", [](const PyMachine& p) {
            return p.toml.empty() ? "nesshi.machine('" + p.m.reference() + "')" : "<nesshi.Machine '" + p.m.name + "' from TOML text>";
        });
    m.def("machine", [](const py::object& spec, const std::string& toml) {
        if (py::isinstance(spec, py::module_::import("os").attr("PathLike"))) return make_machine(path_arg(spec), toml);
        if (!py::isinstance<py::str>(spec))
            throw py::type_error("a machine is a preset name, a TOML file (str or os.PathLike) or TOML text, not " +
                                 py::str(py::type::of(spec).attr("__name__")).cast<std::string>());
        return make_machine(spec.cast<std::string>(), toml);
    }, py::arg("spec") = "os", py::arg("toml") = "",
          "A machine: a preset name (os, ic, seq, os-real, ic-real, seq-real), a TOML file, or TOML text (spec "
          "with a newline or '=', or toml=...). A malformed description raises nesshi.Error at its line and column.");
    m.def("presets", [] {
        std::vector<std::string> names;
        for (std::string_view n : isa::preset_names()) names.emplace_back(n);
        return names;
    }, "The names of the built-in machine presets.");
}

} // namespace nesshi::python
