// nesshi.assemble / disassemble / loop_report and nesshi.Processor: one simulated processor.
#include "convert.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "isa/object.hpp"
#include "iss/channel.hpp"
#include "iss/memory_dump.hpp"
#include "iss/processor.hpp"
#include "iss/stats.hpp"
#include "sched/loop_report.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <bit>
#include <filesystem>
#include <map>
#include <set>

namespace nesshi::python {
namespace {

// An assembled program and the machine it is for.
struct Object {
    isa::ObjectFile obj;
    isa::Machine machine;
    std::string diagnostics; // warnings, as the assembler printed them
};

Object assemble(const py::object& source_obj, const py::object& machine, const std::vector<std::string>& include_dirs) {
    const auto [name, text] = source_arg(source_obj);
    if (machine.is_none()) {
        const std::string header = assembler::header_machine(text); // as the command line picks it
        if (!header.empty()) return assemble(source_obj, py::str(header), include_dirs);
    }
    const isa::Machine m = machine_arg(machine, "os");
    assembler::AsmOptions opts;
    opts.include_dirs = include_dirs;
    const assembler::AsmResult r = assembler::assemble_string(text, name, m, opts);
    if (!r.ok) {
        py::list errors;
        const assembler::AsmMessage* first = nullptr;
        for (const assembler::AsmMessage& e : r.messages) {
            errors.append(py::make_tuple(e.file, e.line, e.col, e.message, e.error));
            if (e.error && !first) first = &e;
        }
        const assembler::AsmMessage none{true, name, 0, 0, "assembly failed"};
        if (!first) first = &none;
        py::object cls = py::module_::import("nesshi").attr("AssemblyError");
        py::object err = cls(r.diagnostics, first->message, first->file, first->line, first->col, errors, r.diagnostics);
        PyErr_SetObject(cls.ptr(), err.ptr());
        throw py::error_already_set();
    }
    return {r.object, m, r.diagnostics};
}

uint16_t reg_index(const std::string& name) {
    if (name.size() >= 2 && (name[0] == 'r' || name[0] == 'f')) {
        const int n = std::atoi(name.c_str() + 1);
        if (std::to_string(n) == name.substr(1) && n >= 0 && n < int(isa::kMaxRegs))
            return iss::flat_reg(name[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float, uint32_t(n));
    }
    throw py::value_error("no register '" + name + "' (r0..r127, f0..f127)");
}

// A float register reads as a Python float, an integer register as a signed int.
py::object reg_value(uint16_t flat, uint32_t bits) {
    if (flat >= isa::kMaxRegs) return py::float_(std::bit_cast<float>(bits));
    return py::int_(static_cast<int32_t>(bits));
}

// The processor and what it owns: a queue for each channel the program uses, breakpoints.
class PyProcessor {
  public:
    PyProcessor(const Object& o, const std::string& engine) {
        if (engine != "fast" && engine != "checked") throw py::value_error("engine is 'fast' or 'checked', not '" + engine + "'");
        prog_ = iss::load_program(o.obj, o.machine);
        p_ = std::make_unique<iss::Processor>(prog_, engine == "checked" ? iss::Engine::Checked : iss::Engine::Fast);
        new_queues();
    }

    // The loaded state: memory, registers and empty FIFO queues (words fed or sent before are gone).
    void reset() {
        p().reset();
        new_queues();
    }

    // Issues n bundles, a slice at a time as run() does (a bundle count stops exactly, so the
    // slices add up): Ctrl-C stops a large count.
    std::string step(uint64_t n) {
        static constexpr uint64_t kSlice = uint64_t(1) << 22;
        iss::Processor& proc = p();
        iss::Status st = iss::Status::Running;
        for (uint64_t left = n; st == iss::Status::Running && left > 0;) {
            const uint64_t now = std::min(kSlice, left);
            left -= now;
            unlocked([&] { st = proc.step(now); });
            if (st == iss::Status::Running && left > 0 && PyErr_CheckSignals() != 0) throw py::error_already_set();
        }
        if (n == 0) st = proc.step(0);
        return std::string(iss::status_name(st));
    }

    // Runs to halt, a fault, a block on a FIFO, the cycle limit or a breakpoint (checked before
    // each bundle once the first has issued, so run() again continues past it). The GIL is
    // released for a slice of cycles at a time, and Ctrl-C (KeyboardInterrupt) is honoured
    // between slices; meanwhile every other call on this Processor raises RuntimeError.
    std::string run(std::optional<uint64_t> max_cycles) {
        static constexpr uint64_t kSlice = uint64_t(1) << 24; // ~0.1 s of the fast engine
        const uint64_t budget = max_cycles.value_or(std::numeric_limits<uint64_t>::max());
        iss::Processor& proc = p();
        const uint64_t start = proc.cycle();
        iss::Status st = iss::Status::Running;
        bool first = true;
        while (st == iss::Status::Running && proc.cycle() - start < budget) {
            const uint64_t end = proc.cycle() - start + std::min(kSlice, budget - (proc.cycle() - start));
            unlocked([&] {
                if (breakpoints_.empty()) {
                    st = proc.run(end - (proc.cycle() - start));
                } else {
                    for (; st == iss::Status::Running && proc.cycle() - start < end; first = false) {
                        if (!first && breakpoints_.count(proc.pc())) break;
                        st = proc.step(1, end - (proc.cycle() - start));
                    }
                }
            });
            if (st == iss::Status::Running && !first && breakpoints_.count(proc.pc())) break;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        }
        return std::string(iss::status_name(st));
    }

    uint32_t address(const py::object& where) const {
        if (py::isinstance<py::int_>(where)) {
            try {
                return where.cast<uint32_t>();
            } catch (const py::cast_error&) {
                throw py::value_error("no bundle " + py::repr(where).cast<std::string>());
            }
        }
        if (!py::isinstance<py::str>(where)) throw py::type_error("a breakpoint is a code label (str) or a bundle index (int)");
        const std::string label = where.cast<std::string>();
        const isa::Symbol* s = prog_->find_symbol(label);
        if (!s) throw py::key_error("no label '" + label + "'");
        if (s->kind != isa::SymbolKind::Code)
            throw py::key_error("'" + label + "' is a data label; a breakpoint takes a code label or a bundle index");
        return s->value;
    }

    py::object read(const std::string& label, std::optional<uint32_t> count, const std::string& dtype) const {
        iss::DumpSpec spec{label, count, iss::DumpFormat::hex};
        std::vector<uint32_t> words;
        try {
            words = iss::dump_memory(p(), spec).words;
        } catch (const std::invalid_argument& e) {
            throw py::key_error(e.what());
        }
        return as_array(words, dtype);
    }

    void write(const std::string& label, const py::object& values, const std::string& dtype) {
        const isa::Symbol* s = prog_->find_symbol(label);
        if (!s || s->kind != isa::SymbolKind::Data) throw py::key_error("no data label '" + label + "'");
        const std::vector<uint32_t> words = as_words(values, dtype);
        for (size_t i = 0; i < words.size(); ++i)
            if (!p().memory().poke(uint32_t(s->value + 4 * i), 4, words[i]))
                throw py::index_error("word " + std::to_string(i) + " after '" + label + "' is outside every memory");
    }

    void feed(uint32_t ch, const py::object& words, const std::string& dtype) {
        (void)p(); // not while it runs: the queue is the processor's
        iss::QueueChannel& q = queue(ch);
        for (uint32_t w : as_words(words, dtype)) q.feed(w);
    }
    py::object received(uint32_t ch, const std::string& dtype) {
        (void)p();
        return as_array(queue(ch).drain_all(), dtype);
    }

    // The processor, unless run() is running it in another thread (with the GIL released).
    iss::Processor& p() const {
        if (busy_) {
            PyErr_SetString(PyExc_RuntimeError, "this Processor is running in another thread");
            throw py::error_already_set();
        }
        return *p_;
    }
    std::set<uint32_t> breakpoints_;

  private:
    // f() with the GIL released; meanwhile the processor is busy (p() refuses other threads). The
    // flag is set and cleared with the GIL held, so no thread sees it half-set.
    template <typename F>
    void unlocked(F f) {
        busy_ = true;
        struct Clear {
            bool& busy;
            ~Clear() { busy = false; } // after the GIL is back (destroyed after `released`)
        } clear{busy_};
        py::gil_scoped_release released;
        f();
    }

    void new_queues() {
        for (uint32_t ch : prog_->channel_ids()) {
            queues_[ch] = std::make_unique<iss::QueueChannel>();
            p_->attach_channel(ch, queues_[ch].get());
        }
    }

    iss::QueueChannel& queue(uint32_t ch) {
        auto it = queues_.find(ch);
        if (it == queues_.end()) throw py::key_error("the program neither sends nor receives on channel " + std::to_string(ch));
        return *it->second;
    }

    // Words as a numpy array of float32, int32 or uint32 (a list when numpy is absent).
    static py::object as_array(const std::vector<uint32_t>& words, const std::string& dtype) {
        check_dtype(dtype);
        py::object np;
        try {
            np = py::module_::import("numpy");
        } catch (const py::error_already_set&) {
            py::list out;
            for (uint32_t w : words)
                out.append(dtype == "f32" ? py::object(py::float_(std::bit_cast<float>(w)))
                                          : dtype == "i32" ? py::object(py::int_(int32_t(w))) : py::object(py::int_(w)));
            return out;
        }
        py::array_t<uint32_t> a(static_cast<py::ssize_t>(words.size()));
        std::copy(words.begin(), words.end(), a.mutable_data());
        return a.attr("view")(np.attr(dtype == "f32" ? "float32" : dtype == "i32" ? "int32" : "uint32"));
    }

    static std::vector<uint32_t> as_words(const py::object& values, const std::string& dtype) {
        check_dtype(dtype);
        std::vector<uint32_t> out;
        for (const py::handle v : values) {
            try {
                if (dtype == "f32") out.push_back(std::bit_cast<uint32_t>(v.cast<float>()));
                else if (dtype == "i32") out.push_back(uint32_t(v.cast<int32_t>()));
                else out.push_back(v.cast<uint32_t>());
            } catch (const py::cast_error&) {
                throw py::value_error("value " + std::to_string(out.size()) + ", " + py::repr(v).cast<std::string>() + ", is not " +
                                      (dtype == "f32" ? "a number" : dtype == "i32" ? "an int32" : "a uint32") +
                                      " (dtype '" + dtype + "')");
            }
        }
        return out;
    }

    static void check_dtype(const std::string& dtype) {
        if (dtype != "f32" && dtype != "i32" && dtype != "u32")
            throw py::value_error("dtype is 'f32', 'i32' or 'u32', not '" + dtype + "'");
    }

    std::shared_ptr<const iss::Program> prog_;
    std::unique_ptr<iss::Processor> p_;
    std::map<uint32_t, std::unique_ptr<iss::QueueChannel>> queues_;
    bool busy_ = false;
};

} // namespace

std::string path_arg(const py::object& path) { return py::str(py::module_::import("os").attr("fspath")(path)); }

Source source_arg(const py::object& source) {
    const bool path_like = py::isinstance(source, py::module_::import("os").attr("PathLike"));
    if (!path_like && !py::isinstance<py::str>(source))
        throw py::type_error("source is text (str) or a file (str or os.PathLike), not " +
                             py::str(py::type::of(source).attr("__name__")).cast<std::string>());
    std::string text = py::str(path_like ? py::module_::import("os").attr("fspath")(source) : source).cast<std::string>();
    // One word with a '/' or a source file's suffix is never code: a path, even when missing
    // (then "cannot open", not "unknown operation").
    const bool one_word = text.find_first_of(" \t\r\n") == std::string::npos;
    const auto ends = [&](std::string_view s) { return text.size() > s.size() && text.ends_with(s); };
    const bool names_file = one_word && (text.find('/') != std::string::npos || ends(".s") || ends(".sa") || ends(".pk"));
    if (path_like || names_file || (text.find('\n') == std::string::npos && std::filesystem::is_regular_file(text)))
        return {text, base::read_file(text)};
    return {"<string>", text};
}

void bind_program(py::module_& m) {
    py::class_<Object>(m, "Object", "An assembled program and the machine it was assembled for.")
        .def_property_readonly("machine", [](const Object& o) { return o.machine.reference(); },
                               "the machine it was assembled for: a preset name or its file")
        .def_property_readonly("bundles", [](const Object& o) { return o.obj.bundle_count(); }, "bundles of code")
        .def_property_readonly("labels", [](const Object& o) {
            py::dict d;
            for (const isa::Symbol& s : o.obj.symbols) d[py::str(s.name)] = s.value;
            return d;
        }, "label -> bundle index (code) or byte address (data)")
        .def_property_readonly("warnings", [](const Object& o) { return o.diagnostics; }, "the assembler's warnings, as printed")
        .def("save", [](const Object& o, const py::object& path) { isa::write_object_file(o.obj, path_arg(path)); },
             py::arg("path"), "Write the object file (nesshi sim and dis read it).")
        .def("to_bytes", [](const Object& o) {
            const std::vector<uint8_t> b = isa::write_object(o.obj);
            return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
        });
    m.def("assemble", &assemble, py::arg("source"), py::arg("machine") = py::none(),
          py::arg("include_dirs") = std::vector<std::string>{},
          "Assemble source text, or a file (a pathlib.Path, or a str naming a file), for a machine (a preset, a TOML "
          "file or a nesshi.Machine; default: the source's '# machine:' line, else os). Raises nesshi.AssemblyError.");
    m.def("load_object", [](const py::object& path, const py::object& machine) {
        isa::ObjectFile obj = isa::read_object_file(path_arg(path));
        return Object{obj, machine_arg(machine, obj.machine), ""};
    }, py::arg("path"), py::arg("machine") = py::none(), "Read an object file (for a machine file: name it).");
    m.def("disassemble", [](const Object& o, bool slots, bool lines) {
        return assembler::disassemble(o.obj, o.machine, {slots, lines});
    }, py::arg("obj"), py::arg("slots") = true, py::arg("lines") = true,
          "Assembly text that re-assembles to the same object (nesshi dis).");
    m.def("loop_report", [](const Object& o, const std::string& label) {
        py::list out;
        for (const sched::LoopReport& l : sched::analyse_loops(o.obj, o.machine, label)) {
            py::dict d = to_python_json_text(l.json());
            d["text"] = l.text();
            out.append(d);
        }
        return out;
    }, py::arg("obj"), py::arg("label") = "",
          "Each loop's II, bounds, resources, lifetimes and reservation table (nesshi loop --json), with 'text'.");

    py::class_<PyProcessor>(m, "Processor", "One simulated processor running an Object (nesshi sim, nesshi debug).")
        .def(py::init<const Object&, const std::string&>(), py::arg("obj"), py::arg("engine") = "fast",
             "engine: 'fast' (trusts the assembler's checks) or 'checked' (ports and hazards checked as it runs)")
        .def("step", &PyProcessor::step, py::arg("bundles") = 1, "Issue this many bundles; returns the status.")
        .def("run", &PyProcessor::run, py::arg("max_cycles") = py::none(),
             "Run until halt, a fault, a FIFO block, max_cycles more cycles or a breakpoint; returns the status: "
             "'running' (stopped at a limit or breakpoint), 'blocked', 'halted' or 'faulted'. Ctrl-C stops it "
             "(KeyboardInterrupt); the GIL is released meanwhile, and other calls on this Processor raise RuntimeError.")
        .def("break_at", [](PyProcessor& p, const py::object& where) {
            (void)p.p(); // not while it runs in another thread
            p.breakpoints_.insert(p.address(where));
        },
             py::arg("where"), "A breakpoint at a code label or bundle index.")
        .def("clear_breakpoints", [](PyProcessor& p) {
            (void)p.p();
            p.breakpoints_.clear();
        })
        .def_property_readonly("breakpoints", [](const PyProcessor& p) { return p.breakpoints_; }, "bundle indices run() stops before")
        .def_property_readonly("cycle", [](const PyProcessor& p) { return p.p().cycle(); }, "cycles run so far (waits and bubbles included)")
        .def_property_readonly("pc", [](const PyProcessor& p) { return p.p().pc(); }, "the bundle to issue next")
        .def_property_readonly("status", [](const PyProcessor& p) { return std::string(iss::status_name(p.p().status())); },
                               "'running', 'blocked' (on a FIFO), 'halted' or 'faulted'")
        .def_property_readonly("fault", [](const PyProcessor& p) -> py::object {
            if (!p.p().fault()) return py::none();
            return py::str(iss::format_fault(p.p().program(), *p.p().fault()));
        }, "The fault report (as nesshi sim prints it), or None.")
        .def("reg", [](const PyProcessor& p, const std::string& name) {
            const uint16_t r = reg_index(name);
            return reg_value(r, p.p().reg(r));
        }, py::arg("name"), "A register's value: 'r5' as a signed int, 'f3' as a float.")
        .def("reg_bits", [](const PyProcessor& p, const std::string& name) { return p.p().reg(reg_index(name)); }, py::arg("name"))
        .def("set_reg", [](PyProcessor& p, const std::string& name, const py::object& v) {
            const uint16_t r = reg_index(name);
            // An f register takes any number but an int (numpy.float32 included) as a float; an int is its bits.
            const bool as_float = r >= isa::kMaxRegs && !PyIndex_Check(v.ptr());
            uint32_t bits = 0;
            try {
                if (as_float) {
                    bits = std::bit_cast<uint32_t>(v.cast<float>());
                } else {
                    const int64_t n = v.cast<int64_t>();
                    if (n < INT32_MIN || n > int64_t(UINT32_MAX)) throw py::cast_error();
                    bits = uint32_t(n);
                }
            } catch (const py::cast_error&) {
                throw py::value_error(name + " takes " + (r >= isa::kMaxRegs ? "a float, or its bits as an int" : "an int") +
                                      " in -2**31 .. 2**32-1, not " + py::repr(v).cast<std::string>());
            }
            p.p().set_reg(r, bits);
        }, py::arg("name"), py::arg("value"),
           "Set a register: an r register to an int (-2**31 .. 2**32-1), an f register to a float (numpy's too), or "
           "to its bits given as an int.")
        .def("read", &PyProcessor::read, py::arg("label"), py::arg("count") = py::none(), py::arg("dtype") = "f32",
             "Memory words at a data label (default: up to the next data label) as a numpy array of f32, i32 or u32.")
        .def("write", &PyProcessor::write, py::arg("label"), py::arg("values"), py::arg("dtype") = "f32",
             "Write words at a data label.")
        .def("inflight", [](const PyProcessor& p) {
            py::list out;
            for (const iss::PendingWrite& w : p.p().inflight())
                out.append(py::dict(py::arg("reg") = iss::reg_name(w.reg), py::arg("value") = reg_value(w.reg, w.value),
                                    py::arg("lands") = w.lands));
            return out;
        }, "Writes in flight, by landing cycle: [{'reg', 'value', 'lands'}].")
        .def("feed", &PyProcessor::feed, py::arg("channel"), py::arg("words"), py::arg("dtype") = "u32",
             "Queue words for the program's recv on a channel.")
        .def("received", &PyProcessor::received, py::arg("channel"), py::arg("dtype") = "u32",
             "The words the program sent on a channel since the last call.")
        .def("stats", [](const PyProcessor& p) { return to_python(iss::stats_json(iss::compute_stats(p.p()))); },
             "The statistics, the same dict as nesshi sim --stats-json.")
        .def("reset", &PyProcessor::reset, "Back to the loaded state: memory, registers, cycle 0, empty FIFO queues.");
}

} // namespace nesshi::python
