// `nesshi sim`: run one processor standalone, print statistics, trace, FIFO files.
#include "status.hpp"
#include "commands.hpp"
#include "fifo_files.hpp"
#include "outputs.hpp"
#include "ranges.hpp"
#include "sim_load.hpp"

#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "iss/channel.hpp"
#include "iss/lockstep.hpp"
#include "iss/memory_dump.hpp"
#include "iss/processor.hpp"
#include "iss/stats.hpp"
#include "iss/trace.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <system_error>

namespace nesshi::cli {

namespace {

struct SimOpts {
    std::string input, machine, stats_json, trace, trace_format = "auto", engine = "fast";
    std::vector<std::string> fifo_in, fifo_out, dump, expect;
    uint64_t max_cycles = 100'000'000, ulp = 0;
    bool quiet = false;
};

// The channels of one processor: inputs fed from files (then closed), outputs collected.
struct Fifos {
    std::map<uint32_t, std::unique_ptr<iss::QueueChannel>> in, out;
    void attach(iss::Processor& p) {
        for (auto& [ch, q] : in) p.attach_channel(ch, q.get());
        for (auto& [ch, q] : out) p.attach_channel(ch, q.get());
    }
};

Fifos make_fifos(const SimOpts& o, const std::vector<std::vector<uint32_t>>& inputs) {
    Fifos f;
    for (size_t i = 0; i < o.fifo_in.size(); ++i) {
        auto [ch, file] = channel_spec(o.fifo_in[i], 0);
        auto q = std::make_unique<iss::QueueChannel>();
        for (uint32_t w : inputs[i]) q->feed(w);
        q->close();
        f.in[ch] = std::move(q);
    }
    for (const auto& spec : o.fifo_out) {
        auto [ch, file] = channel_spec(spec, 1);
        f.out[ch] = std::make_unique<iss::QueueChannel>();
    }
    return f;
}

// --expect SPEC=FILE: the dump spec and the values read from FILE.
struct Expectation {
    iss::DumpSpec spec;
    std::vector<iss::Expected> values;
};

// Parsed and checked before the run: bad specs, unknown labels and unreadable files fail first.
std::vector<Expectation> read_expectations(const SimOpts& o, const iss::Program& prog) {
    std::vector<Expectation> out;
    for (const auto& e : o.expect) {
        const auto eq = e.find('=');
        if (eq == std::string::npos || eq + 1 == e.size())
            throw UsageError(fmt::format("--expect '{}': expected LABEL[:COUNT][:FORMAT]=FILE", e));
        Expectation x;
        const std::string file = e.substr(eq + 1);
        try {
            x.spec = iss::parse_dump_spec(e.substr(0, eq));
        } catch (const std::invalid_argument& err) {
            throw UsageError(err.what());
        }
        x.values = iss::parse_values(base::read_file(file), file, x.spec.format);
        if (!x.spec.count) x.spec.count = static_cast<uint32_t>(std::max<std::size_t>(1, x.values.size()));
        out.push_back(std::move(x));
    }
    for (const auto& d : o.dump) {
        try {
            const iss::DumpSpec spec = iss::parse_dump_spec(d);
            const isa::Symbol* sym = prog.find_symbol(spec.label);
            if (!sym || sym->kind != isa::SymbolKind::Data)
                throw std::invalid_argument(fmt::format("--dump {}: no data label '{}' in {}", d, spec.label, o.input));
        } catch (const std::invalid_argument& err) {
            throw UsageError(err.what());
        }
    }
    for (const auto& x : out) {
        const isa::Symbol* sym = prog.find_symbol(x.spec.label);
        if (!sym || sym->kind != isa::SymbolKind::Data)
            throw UsageError(fmt::format("--expect: no data label '{}' in {}", x.spec.label, o.input));
    }
    return out;
}

// After the run: the dumps on stdout, then the first difference from an expectation, if any.
void dump_and_check(const SimOpts& o, const iss::Processor& p, const std::vector<Expectation>& expect) {
    for (const auto& d : o.dump) fmt::print("{}", iss::dump_memory(p, iss::parse_dump_spec(d)).text());
    for (const auto& x : expect) {
        const iss::Mismatch m = iss::compare(iss::dump_memory(p, x.spec), x.values, o.ulp);
        if (m) throw base::Error(m.message);
    }
}

void run_sim(const SimOpts& o) {
    for (const auto& spec : o.fifo_in) channel_spec(spec, 0); // usage errors first
    // One output may be stdout ('-'); the report then goes to stderr, and --dump (results on
    // stdout) cannot be used with it.
    std::vector<NamedOutput> outs = {{"--trace", o.trace}, {"--stats-json", o.stats_json}};
    for (const auto& spec : o.fifo_out) outs.emplace_back("--fifo-out", channel_spec(spec, 1).second);
    const bool output_on_stdout = stdout_output(outs);
    if (output_on_stdout && !o.dump.empty())
        throw UsageError("--dump prints on stdout, where another output already goes ('-'); give that output a file");
    std::FILE* report = output_on_stdout ? stderr : stdout;
    check_outputs({o.trace, o.stats_json});
    for (const auto& spec : o.fifo_out) check_output(channel_spec(spec, 1).second);
    auto prog = load_sim_input(o.input, o.machine);
    check_channels_used(o.fifo_in, o.fifo_out, o.input, *prog);
    const std::vector<Expectation> expect = read_expectations(o, *prog);
    std::vector<std::vector<uint32_t>> inputs;
    for (const auto& spec : o.fifo_in) inputs.push_back(iss::read_word_file(channel_spec(spec, 0).second));
    bool lockstep = o.engine == "lockstep";
    iss::Processor p(prog, o.engine == "checked" ? iss::Engine::Checked : iss::Engine::Fast);
    Fifos fifos = make_fifos(o, inputs);
    fifos.attach(p);

    std::optional<base::OutputFile> trace_file;
    std::unique_ptr<iss::Tracer> tracer;
    iss::ChromeTracer* chrome_tracer = nullptr;
    if (!o.trace.empty()) {
        trace_file.emplace(o.trace);
        bool chrome = o.trace_format == "chrome" ||
                      (o.trace_format == "auto" && o.trace.size() > 5 && o.trace.ends_with(".json"));
        if (chrome) {
            auto t = std::make_unique<iss::ChromeTracer>(trace_file->get());
            chrome_tracer = t.get();
            tracer = std::move(t);
        } else {
            tracer = std::make_unique<iss::TextTracer>(trace_file->get());
        }
        p.set_tracer(tracer.get());
    }

    std::optional<iss::Fault> fault;
    iss::Status st;
    std::map<uint32_t, std::vector<uint32_t>> outputs;
    // The processor whose state is reported: in lock-step, the checked one when it stopped on a
    // dynamic rule the fast engine trusts (the fast one has issued the faulting bundle already,
    // one cycle or more past the fault), so every engine reports a fault at the same count.
    const iss::Processor* shown = &p;
    std::unique_ptr<iss::Processor> checked;
    try { // the tracers print with fmt, which throws std::system_error when the trace file fails
    if (lockstep) {
        checked = std::make_unique<iss::Processor>(prog, iss::Engine::Checked);
        Fifos fifos2 = make_fifos(o, inputs);
        fifos2.attach(*checked);
        auto r = iss::run_lockstep(p, *checked, o.max_cycles);
        st = r.status;
        fault = r.fault;
        if (checked->status() == iss::Status::Faulted && p.status() != iss::Status::Faulted) shown = checked.get();
        for (auto& [ch, q] : fifos.out) {
            outputs[ch] = q->drain_all();
            if (!fault && outputs[ch] != fifos2.out[ch]->drain_all())
                fault = iss::Fault{iss::FaultKind::Divergence, p.cycle(), p.pc(),
                                   fmt::format("fast and checked engines sent different words on channel {}", ch), {}};
        }
        if (shown != &p) // the words the checked engine sent before its fault
            for (auto& [ch, q] : fifos2.out) outputs[ch] = q->drain_all();
    } else {
        st = p.run(o.max_cycles);
        if (p.fault()) fault = p.fault();
        for (auto& [ch, q] : fifos.out) outputs[ch] = q->drain_all();
    }
    if (tracer) {
        p.set_tracer(nullptr);
        if (chrome_tracer) chrome_tracer->finish();
        tracer.reset();
        trace_file->close();
    }
    } catch (const std::system_error& e) {
        if (!trace_file) throw;
        p.set_tracer(nullptr);
        throw base::WriteError(o.trace, e.code().value());
    }
    if (!fault && st == iss::Status::Running)
        fault = iss::Fault{iss::FaultKind::CycleLimit, p.cycle(), p.pc(),
                           fmt::format("the cycle limit ({}) was reached without halt", o.max_cycles), {}};
    if (!fault && st == iss::Status::Blocked)
        fault = iss::Fault{iss::FaultKind::Deadlock, p.cycle(), p.pc(),
                           fmt::format("blocked on channel {} with nothing left to run", p.blocked_channel()), {}};

    for (const auto& spec : o.fifo_out) {
        auto [ch, file] = channel_spec(spec, 1);
        base::write_file(file, iss::format_words(outputs[ch]));
    }
    iss::Stats s = iss::compute_stats(*shown);
    if (!o.stats_json.empty()) base::write_file(o.stats_json, iss::stats_json(s).dump(2) + "\n");
    if (!o.quiet) {
        // The first line says why the run stopped; the full fault report follows the statistics.
        const bool compiled = o.engine == "fast" && shown->compiled_runs(); // built in, or at run time
        const std::string engine = o.engine + (compiled ? " engine, compiled runs" : " engine");
        if (fault)
            fmt::print(report, "{}: stopped after {} cycles ({}): {}: {}\n", o.input, shown->cycle(), engine,
                       iss::fault_rule(fault->kind), fault->message);
        else
            fmt::print(report, "{}: halted after {} cycles ({})\n", o.input, shown->cycle(), engine);
        fmt::print(report, "{}", iss::stats_text(s));
    }
    if (!fault) dump_and_check(o, p, expect);
    base::flush_stdout(); // the report before the fault on stderr, and checked
    if (fault) {
        status("{}", iss::format_fault(p.program(), *fault));
        throw Reported(kExitFault);
    }
}

} // namespace

void add_sim(CLI::App& app) {
    auto* cmd = app.add_subcommand("sim", "Run a program on the instruction-set simulator and print statistics");
    auto o = std::make_shared<SimOpts>();
    cmd->add_option("input", o->input, "Object file (.o), or assembly source (.s) assembled first")->required();
    cmd->add_option("-m,--machine", o->machine, "Machine preset or TOML file (default: the one the object names; needed when it was assembled with -m FILE; the fingerprint must match)");
    cmd->add_option("--max-cycles", o->max_cycles, "Stop with a fault after this many cycles")
        ->check(between<uint64_t>(1, UINT64_MAX))->capture_default_str();
    cmd->add_option("--fifo-in", o->fifo_in, "[CH=]FILE: words fed to channel CH (default 0); the program must receive on CH");
    cmd->add_option("--fifo-out", o->fifo_out, "[CH=]FILE: words sent on channel CH (default 1; FILE '-': stdout); the program must send on CH");
    cmd->add_option("--stats-json", o->stats_json, "Write statistics as JSON ('-': stdout, and the report goes to stderr)");
    cmd->add_option("--trace", o->trace, "Write a per-cycle trace ('-' for stdout; *.json: Chrome trace events)");
    cmd->add_option("--trace-format", o->trace_format, "auto, text or chrome")
        ->check(CLI::IsMember({"auto", "text", "chrome"}))->capture_default_str()
        ->needs(cmd->get_option("--trace"));
    cmd->add_option("--engine", o->engine, "fast, checked, or lockstep (both, compared every bundle)")
        ->check(CLI::IsMember({"fast", "checked", "lockstep"}))->capture_default_str();
    cmd->add_option("--dump", o->dump, "LABEL[:COUNT][:f32|i32|hex]: print memory at a data label after the run "
                                       "(default: f32, up to the next data label)");
    cmd->add_option("--expect", o->expect, "LABEL[:COUNT][:FORMAT]=FILE: compare memory at LABEL with the values "
                                           "in FILE after the run; the first difference is an error (exit 1)");
    auto* ulp = cmd->add_option("--ulp", o->ulp, "f32 values of --expect may differ by up to N ulps (default 0: exact)")
        ->check(between<uint64_t>(0, UINT32_MAX));
    ulp->needs(cmd->get_option("--expect"));
    cmd->add_flag("-q,--quiet", o->quiet, "Print no statistics");
    cmd->callback([o] { run_sim(*o); });
}

} // namespace nesshi::cli
