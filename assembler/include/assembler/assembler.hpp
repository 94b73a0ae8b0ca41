// Public interface of the assembler and disassembler.
//
//   auto r = assemble_file("loop.s", isa::load_machine("os"), {});
//   if (!r.ok) { fmt::print(stderr, "{}", r.diagnostics); ... }
//   isa::write_object_file(r.object, "loop.o");
//   std::string text = disassemble(r.object, machine);   // re-assembles byte-identically
#pragma once

#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::assembler {

struct AsmOptions {
    std::vector<std::string> include_dirs; // searched by .include after the including file's dir
    bool listing = false;                  // fill AsmResult::listing
    // Stop after this many errors (0: never), as clang's -ferror-limit: the diagnostics end with
    // "fatal error: too many errors emitted, stopping now". Bounds the output of junk input.
    int error_limit = 20;
    // Reads an .include file (the path lexically normalised, e.g. "kernels/abi.inc") into `text`;
    // false when absent. Empty: the file system. Lets embedded sources include each other.
    std::function<bool(const std::string& path, std::string& text)> read_file;
};

// One error or warning, as data (the rendered text is AsmResult::diagnostics): for tools and
// bindings that point at the place themselves. Line and column are 1-based, 0 when unknown.
struct AsmMessage {
    bool error = true; // else a warning
    std::string file;
    int line = 0;
    int col = 0;
    std::string message;
};

struct AsmResult {
    bool ok = false;            // no errors (warnings allowed)
    isa::ObjectFile object;     // valid only when ok
    std::string diagnostics;    // rendered errors/warnings/notes with source line and caret (long
                                // lines cut around it)
    std::string listing;        // when requested
    std::vector<AsmMessage> messages; // the errors and warnings of `diagnostics`, in its order (notes left out)
    int errors = 0;
    int warnings = 0;
};

AsmResult assemble_file(const std::string& path, const isa::Machine& m, const AsmOptions& opts);
// `filename` names the text in diagnostics and in the object's line table.
AsmResult assemble_string(std::string_view text, std::string_view filename, const isa::Machine& m,
                          const AsmOptions& opts);

// The machine a source names on its first line, `# machine: NAME` (how examples and kernels say
// which machine they are for), or empty when that line is absent.
std::string header_machine(std::string_view text);

struct DisOptions {
    bool slots = true; // print each op's issue slot ("fpu0: fadd ..."), needed for byte identity
    bool lines = true; // print .file/.loc so the line table is reproduced
};
// Assembly text that re-assembles (on the same machine) to a byte-identical object.
// Throws isa::ObjectError when the object's machine fingerprint differs from `m`'s, when a word
// does not decode, or when a bundle breaks the machine's bundle rules.
std::string disassemble(const isa::ObjectFile& obj, const isa::Machine& m, const DisOptions& opts = {});

} // namespace nesshi::assembler
