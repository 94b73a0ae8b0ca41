// nesshi.pipeline(): a linear-assembly loop software-pipelined for a machine (nesshi pipeline).
#include "convert.hpp"

#include "assembler/assembler.hpp"
#include "base/error.hpp"
#include "machine/verify_pipeline.hpp"
#include "sched/loop_report.hpp"
#include "sched/pipeline.hpp"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace nesshi::python {
namespace {

struct Pipelined {
    sched::PipelineResult r;
    isa::Machine machine;
    std::string verification;
    std::string text() const { // the file `nesshi pipeline` writes
        return fmt::format("# machine: {}\n{}#   verification: {}\n{}", machine.reference(), r.report, verification, r.code);
    }
};

Pipelined pipeline(const py::object& source, const py::object& machine, int ii, double exact, bool verify, bool shorten) {
    if (ii < 0 || ii > 4096) throw py::value_error(fmt::format("ii must be 0 (search) or an integer between 1 and 4096 (got {})", ii));
    if (!(exact >= 0 && exact <= 86400))
        throw py::value_error(fmt::format("exact must be a number of seconds between 0 and 86400 (got {})", exact));
    const Source src = source_arg(source);
    const std::string header = assembler::header_machine(src.text);
    const isa::Machine m = machine_arg(machine, header.empty() ? "os" : header);
    sched::PipelineOptions po;
    po.ii = ii;
    po.exact_seconds = exact;
    if (shorten) po.shorten = sched::PipelineOptions::Shorten::Always;
    Pipelined p{sched::pipeline_source(src.text, src.name, m, po), m, "not run (verify=False)"};
    if (verify) p.verification = machine::verify_pipeline(src.text, src.name, m, po, p.r);
    return p;
}

} // namespace

void bind_pipeline(py::module_& m) {
    py::class_<Pipelined>(m, "Pipelined", "A software-pipelined loop: the report as data, and the code.")
        .def_property_readonly("ii", [](const Pipelined& p) { return p.r.ii; }, "the initiation interval taken (the first region's)")
        .def_property_readonly("mii", [](const Pipelined& p) { return p.r.mii; }, "max(res_mii, rec_mii): the bound")
        .def_property_readonly("res_mii", [](const Pipelined& p) { return p.r.res_mii; }, "the resource bound (slots, ports)")
        .def_property_readonly("rec_mii", [](const Pipelined& p) { return p.r.rec_mii; }, "the recurrence bound")
        .def_property_readonly("stages", [](const Pipelined& p) { return p.r.stages; }, "iterations in flight in the kernel")
        .def_property_readonly("unroll", [](const Pipelined& p) { return p.r.unroll; }, "kernel copies")
        .def_property_readonly("min_pipelined_trip", [](const Pipelined& p) { return p.r.min_pipelined_trip; },
                               "smaller trip counts run the sequential copy only")
        .def_property_readonly("is_while", [](const Pipelined& p) { return p.r.is_while; }, "a .pipeline while region (a data-dependent exit)")
        .def_property_readonly("registers", [](const Pipelined& p) { return p.r.scratch; },
                               "physical registers the tool allocated")
        .def_property_readonly("source_registers", [](const Pipelined& p) { return p.r.source_registers; },
                               "registers the source names (live across the region)")
        .def_property_readonly("regions", [](const Pipelined& p) {
            py::list out;
            for (const sched::LoopSummary& l : p.r.loops) out.append(to_python_json_text(l.json()));
            return out;
        }, "each .pipeline region, in file order, as nesshi pipeline --json writes it (II, bounds, stages, unroll, and "
           "with .trip the whole-run cycles the schedule was chosen by)")
        .def_property_readonly("svgs", [](const Pipelined& p) {
            std::vector<std::string> out;
            for (const sched::LoopSummary& l : p.r.loops) out.push_back(l.svg);
            return out;
        }, "each region's schedule as a picture (SVG text), as nesshi pipeline --svg draws it: the modulo reservation "
           "table with its ops coloured by iteration stage, and the lifetimes")
        .def_property_readonly("verification", [](const Pipelined& p) { return p.verification; }, "what was checked, as the report says")
        .def_property_readonly("report", [](const Pipelined& p) { return p.r.report; }, "the report block, as text")
        .def_property_readonly("code", [](const Pipelined& p) { return p.text(); },
                               "the pipelined file, as nesshi pipeline writes it")
        .def_property_readonly("sequential", [](const Pipelined& p) { return p.r.linear; },
                               "the region's sequential meaning (what verification compares with)")
        .def("loop_report", [](const Pipelined& p) {
            const assembler::AsmResult a = assembler::assemble_string(p.text(), "<pipelined>", p.machine, {});
            if (!a.ok) throw base::Error("the pipelined code does not assemble:\n" + a.diagnostics);
            py::list out;
            for (const sched::LoopReport& l : sched::analyse_loops(a.object, p.machine)) {
                py::dict d = to_python_json_text(l.json());
                d["text"] = l.text();
                out.append(d);
            }
            return out;
        }, "The assembled code's loops: II, resources, lifetimes and the modulo reservation table (nesshi loop).");
    m.def("pipeline", &pipeline, py::arg("source"), py::arg("machine") = py::none(), py::arg("ii") = 0,
          py::arg("exact") = 0.0, py::arg("verify") = true, py::arg("shorten") = false,
          "Software-pipeline the .pipeline region(s) of linear assembly (text or a file) for a machine (default: the "
          "file's '# machine:' line, else os). ii: this II only; exact: seconds of exact search (Gecode) below the II found; "
          "shorten: the solver's shortest iteration at that II whatever the trip count (by default only where .trip says runs are short). "
          "verify (default): the code runs against its sequential meaning on random data, or nesshi.Error is raised.");
}

} // namespace nesshi::python
