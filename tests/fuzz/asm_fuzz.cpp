// Fuzz target `asm`: assembly source text on the machine its `# machine:` line names (else on
// every preset). Errors must be reported with a location; whatever assembles must disassemble,
// re-assemble byte-identically and load into the ISS.
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "iss/program.hpp"
#include "kernels/sources.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

using namespace nesshi;

namespace {

// `.include` sees the embedded kernel sources only (by the end of the path), never the disk.
bool embedded_include(const std::string& path, std::string& text) {
    for (const kernels::SourceFile& f : kernels::embedded_sources())
        if (path.size() >= f.path.size() && path.compare(path.size() - f.path.size(), f.path.size(), f.path) == 0) {
            text = f.text;
            return true;
        }
    return false;
}

void assemble_on(std::string_view text, const isa::Machine& m) {
    assembler::AsmOptions opts;
    opts.read_file = embedded_include;
    const assembler::AsmResult r = assembler::assemble_string(text, "fuzz.s", m, opts);
    if (!r.ok) {
        fuzz::check(r.errors > 0 && r.diagnostics.find("error") != std::string::npos,
                    "a rejected source reports an error", r.diagnostics);
        return;
    }
    const std::string dis = assembler::disassemble(r.object, m);
    const assembler::AsmResult again = assembler::assemble_string(dis, "dis.s", m, {});
    fuzz::check(again.ok, "the disassembly re-assembles", dis + again.diagnostics);
    fuzz::check(isa::write_object(again.object) == isa::write_object(r.object),
                "the disassembly re-assembles byte-identically", dis);
    if (r.object.code.empty()) return; // an ISS program needs code (abi.inc alone has none)
    for (const isa::DataSection& d : r.object.data) // the assembler places data anywhere; the loader
        if (!d.bytes.empty() && !m.memory_at(d.address, uint32_t(d.bytes.size()))) return; // wants a region
    try {
        (void)iss::load_program(r.object, m);
    } catch (const base::Error& e) {
        fuzz::fail("an assembled object loads into the ISS", e.what());
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<isa::Machine>& presets = fuzz::presets();
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const std::string header = assembler::header_machine(text);
    const bool named = isa::is_preset(header);
    for (const isa::Machine& m : presets)
        if (!named || header == m.name) assemble_on(text, m);
    return 0;
}
