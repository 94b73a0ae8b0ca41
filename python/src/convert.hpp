// What the bindings share: JSON values to Python objects, and a machine argument (a preset name,
// a TOML file, or a nesshi.Machine) as a loaded description or as what the libraries take by name.
#pragma once

#include "isa/machine.hpp"
#include "kbuild/stage_machine.hpp"

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

#include <string>

namespace nesshi::python {
namespace py = pybind11;

// A JSON value as dicts, lists, str, int, float, bool and None (json.loads of its text, so the
// result is exactly what the command line's JSON file reads back as).
py::object to_python(const nlohmann::json& j);
py::object to_python_json_text(const std::string& text);

// A nesshi.Machine, or a str naming a preset or a TOML file; None gives `fallback`.
isa::Machine machine_arg(const py::handle& arg, const std::string& fallback);
// The same as a stage option of machine::Options: a Machine as it is (one made from TOML text is
// named by its name in provenance), a str naming a preset or a file or holding TOML text, or None
// for `preset`.
kbuild::StageMachine stage_machine(const py::handle& arg, const char* preset);

// A source argument: a path (os.PathLike, a str naming an existing file and holding no newline, or
// one word with a '/' or ending .s, .sa or .pk) read from disk, else the text itself, named
// "<string>" in diagnostics. Anything but a str or an os.PathLike raises TypeError.
struct Source {
    std::string name, text;
};
Source source_arg(const py::object& source);
// A file name given as a str or an os.PathLike.
std::string path_arg(const py::object& path);

void bind_machine(py::module_& m);
void bind_program(py::module_& m);
void bind_pipeline(py::module_& m);
void bind_render(py::module_& m);

} // namespace nesshi::python
