// The `nesshi` Python module: the libraries' public interfaces, no logic of their own. Errors are
// nesshi.Error (file, line, column, message as the command line prints them); an assembly that
// fails raises nesshi.AssemblyError with the first error's place and every diagnostic.
#include "convert.hpp"

#include "base/error.hpp"
#include "machine/provenance.hpp"

#include <pybind11/eval.h>
#include <pybind11/stl.h>

namespace nesshi::python {

py::object to_python_json_text(const std::string& text) { return py::module_::import("json").attr("loads")(text); }
py::object to_python(const nlohmann::json& j) { return to_python_json_text(j.dump()); }

} // namespace nesshi::python

PYBIND11_MODULE(nesshi, m) {
    namespace py = pybind11;
    using namespace nesshi::python;
    m.doc() = "Nesshisen: toolchain and simulator for the VLIW processors of a 1993 ray-tracing machine.\n\n"
              "machine(), presets(), assemble(), load_object(), disassemble(), loop_report(), Processor, pipeline(), scene(), "
              "render().\n\nA library's error raises nesshi.Error (nesshi.AssemblyError for assembly) with the command "
              "line's message; a wrong argument raises TypeError, ValueError or KeyError.\n\nKernels scheduled for a "
              "machine other than the presets are kept on disk as the command line keeps them (under "
              "$XDG_CACHE_HOME/nesshi/kernels; NESSHI_CACHE_DIR names another folder, empty turns it off).";
    m.attr("__version__") = NESSHI_VERSION;
    // The exception classes are Python classes (attributes as keyword arguments), made once here.
    py::dict ns;
    ns["__name__"] = "nesshi"; // so the classes are nesshi.Error and nesshi.AssemblyError in tracebacks
    py::exec(R"(
class Error(Exception):
    """A Nesshisen error: `message` without its place; `file`, `line`, `column` when known (else None / 0).
    str(e) is the command line's text: "file:line:col: error: message"."""
    def __init__(self, text, message=None, file=None, line=0, column=0):
        super().__init__(text)
        self.message = text if message is None else message
        self.file, self.line, self.column = file, line, column

class AssemblyError(Error):
    """Assembly failed. The place and message are the first error's; `errors` lists every error and
    warning as (file, line, column, message, is_error); `diagnostics` is the rendered text."""
    def __init__(self, text, message=None, file=None, line=0, column=0, errors=(), diagnostics=None):
        super().__init__(text, message, file, line, column)  # defaults: pickle (multiprocessing) rebuilds it from text
        self.errors, self.diagnostics = list(errors), text if diagnostics is None else diagnostics
)", ns);
    m.attr("Error") = ns["Error"];
    m.attr("AssemblyError") = ns["AssemblyError"];
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const nesshi::base::Error& e) {
            py::object cls = py::module_::import("nesshi").attr("Error");
            const auto& loc = e.loc();
            py::object err = cls(e.what(), e.message(), loc.known() ? py::object(py::str(*loc.file)) : py::object(py::none()),
                                 loc.line, loc.col);
            PyErr_SetObject(cls.ptr(), err.ptr());
        } catch (const py::builtin_exception&) {
            throw; // pybind11's own (cast_error, value_error, ...): its translator
        } catch (const std::runtime_error& e) {
            // The libraries' other failures ("cache line must be a power of two", "the PE passed
            // the cycle limit"): the command line prints them as errors too.
            py::object cls = py::module_::import("nesshi").attr("Error");
            PyErr_SetObject(cls.ptr(), cls(e.what()).ptr());
        }
    });
    bind_machine(m);
    bind_program(m);
    bind_pipeline(m);
    bind_render(m);
    // As the command line does (cli/main.cpp): a study renders many scenes on one description.
    nesshi::machine::enable_default_schedule_cache();
}
