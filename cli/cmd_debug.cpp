// `nesshi debug`: single-step a program (interactive with line editing, or from a script).
#include "commands.hpp"
#include "fifo_files.hpp"
#include "sim_load.hpp"

#include "iss/channel.hpp"
#include "iss/debugger.hpp"
#include "iss/processor.hpp"

#include <fmt/core.h>

#include <map>
#include <memory>

namespace nesshi::cli {

namespace {
struct DebugOpts {
    std::string input, machine, script, engine = "checked";
    std::vector<std::string> fifo_in;
};

void run_debug(const DebugOpts& o) {
    auto prog = load_sim_input(o.input, o.machine);
    iss::Processor p(prog, o.engine == "fast" ? iss::Engine::Fast : iss::Engine::Checked);
    // Channels: inputs from word files ([CH=]FILE, default channel 0); every other channel the
    // program uses gets an unbounded queue, so sends never block. `run` and `restart` make them
    // again (the inputs refilled, the outputs emptied).
    std::vector<std::pair<uint32_t, std::vector<uint32_t>>> inputs;
    check_channels_used(o.fifo_in, {}, o.input, *prog);
    for (const auto& spec : o.fifo_in) {
        const auto [ch, file] = channel_spec(spec, 0);
        inputs.emplace_back(ch, iss::read_word_file(file));
    }
    std::map<uint32_t, std::unique_ptr<iss::QueueChannel>> chans;
    auto attach_channels = [&] {
        chans.clear();
        for (const auto& [ch, words] : inputs) {
            auto q = std::make_unique<iss::QueueChannel>();
            for (uint32_t w : words) q->feed(w);
            q->close();
            chans[ch] = std::move(q);
        }
        for (const auto& d : prog->ops()) {
            auto k = d.instr.info().kind;
            if ((k == isa::Kind::Recv || k == isa::Kind::Send) && !chans.count(d.imm)) {
                auto q = std::make_unique<iss::QueueChannel>();
                if (k == isa::Kind::Recv) q->close();
                chans[d.imm] = std::move(q);
            }
        }
        for (auto& [ch, q] : chans) p.attach_channel(ch, q.get());
    };
    attach_channels();

    iss::Debugger dbg(p, stdout);
    dbg.on_restart = attach_channels;
    fmt::print("nesshi debug: {} on {} ({} bundles, {} engine); 'help' lists commands\n", o.input,
               prog->machine().name, prog->size(), o.engine);
    dbg.execute("disas");
    if (!o.script.empty()) {
        iss::debug_script(dbg, o.script, stdout);
    } else {
        iss::debug_interactive(dbg);
    }
    std::fflush(stdout);
}
} // namespace

void add_debug(CLI::App& app) {
    auto* cmd = app.add_subcommand("debug", "Single-step a program: breakpoints, watches, registers, in-flight writes");
    auto o = std::make_shared<DebugOpts>();
    cmd->add_option("input", o->input, "Object file (.o), or assembly source (.s) assembled first")->required();
    cmd->add_option("-m,--machine", o->machine, "Machine (default: the one the object names)");
    cmd->add_option("--script", o->script, "Run debugger commands from FILE instead of the terminal");
    cmd->add_option("--fifo-in", o->fifo_in, "[CH=]FILE: words fed to channel CH (default 0)");
    cmd->add_option("--engine", o->engine, "checked (default: reports dynamic rule breaks) or fast")
        ->check(CLI::IsMember({"fast", "checked"}))->capture_default_str();
    cmd->callback([o] { run_debug(*o); });
}

} // namespace nesshi::cli
