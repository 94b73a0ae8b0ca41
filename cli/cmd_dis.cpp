// `nesshi dis`: print an object as assembly that re-assembles to the same bytes.
#include "commands.hpp"
#include "errors.hpp"

#include "assembler/assembler.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <fmt/core.h>

#include <memory>

namespace nesshi::cli {
void add_dis(CLI::App& app) {
    auto* cmd = app.add_subcommand("dis", "Disassemble an object file");
    struct Opts {
        std::string input, machine;
        bool no_slots = false, no_lines = false;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("input", o->input, "Object file (.o)")->required();
    cmd->add_option("-m,--machine", o->machine,
                    "Machine preset or TOML file (default: the object's machine, when a preset; the fingerprint must match)");
    cmd->add_flag("--no-slots", o->no_slots, "Omit slot prefixes (the output no longer pins slots)");
    cmd->add_flag("--no-lines", o->no_lines, "Omit .file/.loc line-table directives");
    cmd->callback([o] {
        try {
            isa::ObjectFile obj = isa::read_object_file(o->input);
            std::string name = o->machine.empty() ? obj.machine : o->machine;
            if (o->machine.empty() && !isa::is_preset(name))
                throw isa::ObjectError(base::SourceLoc(o->input),
                                       fmt::format("assembled for machine '{}', which is not a preset: name its description with "
                                                   "-m FILE (the object's fingerprint checks that it is the same machine)",
                                                   name));
            isa::Machine m = isa::load_machine(name);
            assembler::DisOptions opts;
            opts.slots = !o->no_slots;
            opts.lines = !o->no_lines;
            fmt::print("{}", assembler::disassemble(obj, m, opts));
        } catch (const isa::ObjectError& e) { // the decoder's errors name no file
            if (e.loc().known()) throw;
            throw isa::ObjectError(base::SourceLoc(o->input), e.message());
        }
    });
}
} // namespace nesshi::cli
