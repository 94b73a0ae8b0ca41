#include "machine/runner.hpp"

#include "assembler/assembler.hpp"
#include "sched/block.hpp"

#include <stdexcept>

namespace nesshi::machine {

namespace {

// Whether `m` is the machine the scheduled kernel `text` names on its first line (same fingerprint).
bool scheduled_for(std::string_view text, const isa::Machine& m) {
    const std::string name = assembler::header_machine(text);
    return !name.empty() && isa::is_preset(name) && isa::load_machine(name).fingerprint() == m.fingerprint();
}

} // namespace

std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const isa::Machine& m) {
    // Named "kernels/<path>" in diagnostics and line tables, so its "../abi.inc" is "kernels/abi.inc".
    static const std::string kPrefix = "kernels/";
    assembler::AsmOptions opts;
    opts.read_file = [&](const std::string& p, std::string& text) {
        if (p.compare(0, kPrefix.size(), kPrefix) != 0 || !sources.has(p.substr(kPrefix.size()))) return false;
        text = sources.text(p.substr(kPrefix.size()));
        return true;
    };
    std::string text = sources.text(path);
    std::string name = kPrefix + path;
    const std::string pk = path.substr(0, path.rfind('.')) + ".pk";
    if (!scheduled_for(text, m) && sources.has(pk)) { // another machine: schedule its blocks for m
        name = kPrefix + pk;
        text = sched::pack_source(sources.text(pk), name, m, opts).text;
    }
    assembler::AsmResult r = assembler::assemble_string(text, name, m, opts);
    if (!r.ok)
        throw std::runtime_error(name + " (" + sources.origin + ") does not assemble for machine '" + m.name +
                                 "' (" + m.source + "):\n" + r.diagnostics);
    return iss::load_program(r.object, m);
}

std::shared_ptr<const iss::Program> assemble_kernel(const kernels::SourceSet& sources, const std::string& path,
                                                    const std::string& machine) {
    return assemble_kernel(sources, path, isa::load_machine(machine));
}

KernelRunner::KernelRunner(std::shared_ptr<const iss::Program> program, iss::Engine engine)
    : prog(std::move(program)), proc(std::make_unique<iss::Processor>(prog, engine)) {
    proc->attach_channel(0, &in);
    proc->attach_channel(1, &out1);
    proc->attach_channel(2, &out2);
}

void KernelRunner::run(std::uint64_t max_cycles) {
    const iss::Status s = proc->run(max_cycles);
    if (s != iss::Status::Blocked || proc->blocked_channel() != 0)
        throw std::runtime_error("kernel did not wait for input: " + proc->fault_report());
}

} // namespace nesshi::machine
