// `nesshi asm`: assemble a source file into an object (diagnostics to stderr, exit 1 on error).
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "outputs.hpp"
#include "source_machine.hpp"

#include "assembler/assembler.hpp"
#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <fmt/core.h>

#include <memory>

namespace nesshi::cli {
void add_asm(CLI::App& app) {
    auto* cmd = app.add_subcommand("asm", "Assemble a VLIW source file into an object file");
    struct Opts {
        std::string machine, input, output, listing;
        std::vector<std::string> includes;
    };
    auto o = std::make_shared<Opts>();
    cmd->add_option("-m,--machine", o->machine,
                    "Machine preset (os, ic, seq, os-real, ...) or TOML file; default: the source's "
                    "'# machine: NAME' first line, else os");
    cmd->add_option("input", o->input, "Assembly source (.s)")->required();
    cmd->add_option("-o,--output", o->output, "Object file (default: input with .o; '-': stdout)");
    cmd->add_option("--listing", o->listing, "Write a listing (encodings, slots, port usage); '-': stdout");
    cmd->add_option("-I,--include-dir", o->includes, "Directory searched by .include");
    cmd->callback([o] {
        stdout_output({{"-o", o->output}, {"--listing", o->listing}});
        check_outputs({o->output, o->listing});
        // The file is read here only for its header: with -m, a missing file is the assembler's error.
        const isa::Machine m = source_machine(o->machine, o->machine.empty() ? base::read_file(o->input) : "");
        assembler::AsmOptions opts;
        opts.include_dirs = o->includes;
        opts.listing = !o->listing.empty();
        auto r = assembler::assemble_file(o->input, m, opts);
        status("{}", r.diagnostics);
        if (!r.ok) throw Reported(kExitInput);
        std::string out = o->output;
        if (out.empty()) {
            auto dot = o->input.find_last_of('.');
            auto slash = o->input.find_last_of('/');
            bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
            out = (has_ext ? o->input.substr(0, dot) : o->input) + ".o";
        }
        isa::write_object_file(r.object, out);
        if (!o->listing.empty()) base::write_file(o->listing, r.listing);
    });
}
} // namespace nesshi::cli
