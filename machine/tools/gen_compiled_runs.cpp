// Writes the compiled runs of the built-in kernels (iss/compiled.hpp): one C++ function per straight
// run of each program, with its operations' register indices and immediates as constants.
//
//   nesshi_gen_compiled_runs OUTDIR os/dda.s@os ic/intersect.s@ic:4 ...
//
// Each KERNEL@MACHINE is assembled as a machine run assembles it (machine::assemble_kernel on the
// embedded sources; a KERNEL that is a .pk, an alternative source such as ic/intersect.loops.pk,
// by machine::assemble_source, as a preset's render weighs it) and written to OUTDIR/<id>.cpp (its tables) and OUTDIR/<id>_0.cpp ..
// <id>_{PARTS-1}.cpp (its runs; PARTS 1 unless given); OUTDIR/register.cpp registers them all. Run by
// the build (machine/CMakeLists.txt), never by hand. The generated code calls only the helpers of
// iss/src/compiled.hpp (Counts, op<>, end<>, jump<>, jump_to<>, stop, leave), so the semantics stay
// those of isa::kOps.
#include "compiled_runs.hpp"

#include "machine/runner.hpp"

#include "compiled.hpp" // iss/src: op_direct

#include "isa/printer.hpp"
#include "iss/program.hpp"
#include "kernels/sources.hpp"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace nesshi::machine::detail {
void register_compiled_runs() {} // the generator assembles the kernels; it runs none of them
} // namespace nesshi::machine::detail


namespace {

using namespace nesshi;

std::string ident(const std::string& spec) {
    std::string id;
    for (char ch : spec) id += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return id;
}

// The tail of bundle `pc`'s last op, as Program builds it (program.cpp); checked against the
// handler Program chose, so that the generated code cannot drift from the threaded form.
struct Tail {
    enum Kind { Exit, End, Jump } kind = Exit;
    bool commit = false, events = false, gate = false;
};

Tail tail_of(const iss::Program& prog, uint32_t pc) {
    namespace d = iss::detail;
    const iss::DecodedBundle& b = prog.bundles()[pc];
    Tail t;
    bool halt = false;
    for (uint32_t i = b.first; i < b.first + b.count; ++i) {
        const iss::DecodedOp& op = prog.ops()[i];
        const isa::Kind k = op.instr.info().kind;
        halt |= k == isa::Kind::Halt;
        if (k == isa::Kind::Load || k == isa::Kind::Store) t.events = true;
        if (op.dst != iss::kNoReg && op.latency == 1 && !d::op_direct(op)) t.commit = true;
    }
    t.gate = pc + 1 < prog.size() && prog.bundles()[pc + 1].slow; // the next bundle has a FIFO gate
    t.kind = b.control && !halt && prog.machine().branch_penalty == 0 ? Tail::Jump
             : b.run == 1                                            ? Tail::Exit
                                                                     : Tail::End;
    const int commit = t.commit ? d::kEndCommit : 0;
    const int tail = t.kind == Tail::Jump ? d::kJump + commit
                     : t.kind == Tail::Exit ? d::kExit
                                            : d::kEnd + commit + (t.events ? d::kEndEvents : 0) + (t.gate ? d::kEndGate : 0);
    const iss::DecodedOp& last = prog.ops()[b.first + b.count - 1];
    if (last.tfn != d::threaded_handler(last.instr.opcode, d::op_direct(last), tail))
        throw std::runtime_error(fmt::format("bundle {}: the generator's tail {} is not the threaded form's", pc, tail));
    return t;
}

// The one control op of control bundle `pc` when its target is a constant (branch, jump, jal),
// else nullptr (jr, or more than one).
const iss::DecodedOp* constant_jump(const iss::Program& prog, uint32_t pc) {
    const iss::DecodedBundle& b = prog.bundles()[pc];
    const iss::DecodedOp* found = nullptr;
    int control = 0;
    for (uint32_t i = b.first; i < b.first + b.count; ++i) {
        const isa::Kind k = prog.ops()[i].instr.info().kind;
        if (k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink) found = &prog.ops()[i];
        control += k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink || k == isa::Kind::JumpReg;
    }
    return control == 1 ? found : nullptr;
}

// Between the items of an array initializer, `per_line` a line.
const char* sep(uint32_t i, uint32_t per_line) { return i == 0 ? "\n    " : i % per_line ? ", " : ",\n    "; }

// The program's code in `parts` files: <id>.cpp declares the runs and holds the tables, and the
// runs go to <id>_0.cpp .. <id>_{parts-1}.cpp in order, in parts of about equal size, so that one big
// kernel is several compilations that the cores share.
std::vector<std::string> program_code(const iss::Program& prog, const std::string& spec, const std::string& id,
                                      uint32_t parts) {
    const uint32_t nb = prog.size();
    // Runs: a bundle continues the run of the one before when that one's run is longer than 1.
    std::vector<uint32_t> run_of(nb), starts;
    for (uint32_t pc = 0; pc < nb; ++pc) {
        if (pc == 0 || prog.bundles()[pc - 1].run == 1) starts.push_back(pc);
        run_of[pc] = uint32_t(starts.size() - 1);
    }
    const std::string header = fmt::format("// Generated by nesshi_gen_compiled_runs from the built-in kernel {}; do not edit.\n"
                                           "#include \"compiled.hpp\"\n#include \"iss/compiled.hpp\"\n\n"
                                           "namespace nesshi::iss::detail::{} {{\n",
                                           spec, id);
    std::vector<std::string> code(starts.size()); // by run
    std::string out;
    // Ring landings (compiled.hpp's Probe, NoRing, Ring). A run entered at its first bundle f (by
    // the entry switch or a goto) in cycle C issues bundle f + o in cycle C + o until its first
    // control bundle (a stall stops it); the end of bundle j lands cycle C + (j + 1 - f). A write
    // landing then was pushed in cycle C' = C + (j + 1 - f) - L, L <= max_lat: when C' >= C, by
    // bundle f + (C' - C) of this entry, whose pushes the generator knows (a push that does not
    // happen is a faulting load's, whose bundle stops the run); when C' < C, before the entry,
    // possible only while j + 1 - f < max_lat. So past the
    // first max_lat - 1 ends the entry at f lands exactly what its own bundles pushed, in the
    // order they pushed it (bundle, then op order); entries anywhere else (by the switch or a
    // goto) run a second copy of the run that probes at every end.
    uint32_t max_lat = 1;
    for (const iss::DecodedOp& d : prog.ops()) max_lat = std::max(max_lat, d.latency);
    for (uint32_t r = 0; r < starts.size(); ++r) {
        const uint32_t first = starts[r], end = r + 1 < starts.size() ? starts[r + 1] : nb;
        out = fmt::format("\n// bundles {}..{}\n[[gnu::hot]] bool run_{}(Core& c) {{\n    Counts n(c);\n    switch (c.pc) {{\n",
                          first, end - 1, r);
        out += fmt::format("    case {0}: goto f{0};\n", first);
        for (uint32_t pc = first + 1; pc < end; ++pc) out += fmt::format("    case {0}: goto b{0};\n", pc);
        out += "    default: __builtin_unreachable();\n    }\n";
        auto label = [first](uint32_t pc) { return fmt::format("{}{}", pc == first ? 'f' : 'b', pc); };
        // Bundle pc's code; `lands`: by bundle end, the registers of the writes pushed by the copy
        // that land then, in push order (fast copy).
        auto bundle_code = [&](uint32_t pc, bool fast, std::map<uint32_t, std::vector<uint16_t>>& lands) {
            const iss::DecodedBundle& b = prog.bundles()[pc];
            if (b.count == 0) throw std::runtime_error(fmt::format("{}: bundle {} has no op", spec, pc));
            std::set<uint32_t> targets; // constant branch targets inside this run
            for (uint32_t i = b.first; i < b.first + b.count; ++i) {
                const iss::DecodedOp& d = prog.ops()[i];
                const isa::Kind k = d.instr.info().kind;
                if (k == isa::Kind::Nop) continue;
                if ((k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink) && d.imm >= first &&
                    d.imm < end)
                    targets.insert(d.imm);
                const bool ring = !iss::detail::op_direct(d) && d.latency > 1;
                // The kinds whose semantics put a result (handlers.hpp); a load only if it does not fault.
                if (ring && (k == isa::Kind::Compute || k == isa::Kind::Load || k == isa::Kind::JumpLink ||
                             k == isa::Kind::Recv))
                    lands[pc + d.latency - 1].push_back(d.dst);
                out += fmt::format("    op<{}, {}>(c, n.cycle({}), {}, {}, {}, {}, 0x{:x}u, {}, {}, {}); // {}\n", int(d.instr.opcode),
                                   iss::detail::op_direct(d), pc, d.dst, d.a, d.b, d.c, d.imm, d.latency, d.index, d.bundle,
                                   isa::format_instr(d.instr));
            }
            const Tail t = tail_of(prog, pc);
            if (t.kind == Tail::Exit) {
                out += fmt::format("    return stop(c, n, {});\n", pc);
            } else if (t.kind == Tail::End) {
                const std::string land = !fast || pc + 1 - first < max_lat ? "Probe"
                                         : lands.count(pc)                  ? fmt::format("Ring<{}>", fmt::join(lands[pc], ", "))
                                                                            : "NoRing";
                out += fmt::format("    if (!end<{}, {}, {}, {}, {}, {}>(c, n, {})) return false;\n", t.commit, t.events,
                                   t.gate, b.lat1_writes[0], b.lat1_writes[1], land, pc);
            } else if (const iss::DecodedOp* j = constant_jump(prog, pc)) {
                // Taken to j->imm, or (a branch) not taken to pc + 1: stops where jump() would.
                const bool cond = j->instr.info().kind == isa::Kind::Branch;
                out += fmt::format("    if (jump_held(c, n, {})) return stop(c, n, {});\n", pc, pc);
                auto go = [&](bool taken, uint32_t to) {
                    std::string s = taken && cond ? "    if (c.event) {\n" : "    {\n";
                    if (to >= nb) {
                        s += fmt::format("        return stop(c, n, {});\n    }}\n", pc);
                        return s;
                    }
                    s += fmt::format("        if (!jump_to<{}, {}, {}, {}, {}>(c, n, {}, {})) return false;\n", t.commit,
                                     taken, bool(prog.bundles()[to].slow), b.lat1_writes[0], b.lat1_writes[1], pc, to);
                    if (to >= first && to < end)
                        s += fmt::format("        n.go({}, {});\n        goto {};\n    }}\n", pc, to, label(to));
                    else
                        s += fmt::format("        return leave(c, n, {}, {});\n    }}\n", pc, to);
                    return s;
                };
                out += go(true, j->imm);
                if (cond) out += go(false, pc + 1);
            } else {
                out += fmt::format("    {{\n        const uint32_t to = jump<{}, {}, {}>(c, n, {});\n", t.commit,
                                   b.lat1_writes[0], b.lat1_writes[1], pc);
                for (uint32_t to : targets)
                    out += fmt::format("        if (to == {0}) {{\n            n.go({1}, {0});\n            goto {2};\n        }}\n",
                                       to, pc, label(to));
                out += fmt::format("        if (to == kStopped) return false;\n        return leave(c, n, {}, to);\n    }}\n", pc);
            }
            return t.kind;
        };
        // The copy entered at `first`, up to its first bundle that does not go straight on.
        std::map<uint32_t, std::vector<uint16_t>> lands, none;
        out += fmt::format("f{}:\n", first);
        for (uint32_t pc = first;; ++pc) {
            if (pc == end) throw std::runtime_error(fmt::format("{}: run {} ends going straight on", spec, r));
            if (bundle_code(pc, true, lands) != Tail::End) break;
        }
        // The copy entered anywhere else.
        for (uint32_t pc = first + 1; pc < end; ++pc) {
            out += fmt::format("b{}:\n", pc);
            bundle_code(pc, false, none);
        }
        out += "}\n";
        code[r] = std::move(out);
    }
    // The parts: consecutive runs, each part closed once it holds its share of the code.
    size_t total = 0;
    for (const std::string& c : code) total += c.size();
    std::vector<std::string> files(parts + 1, header);
    size_t done = 0;
    uint32_t part = 0;
    for (const std::string& c : code) {
        files[1 + part] += c;
        done += c.size();
        while (part + 1 < parts && done * parts >= total * (part + 1)) ++part;
    }
    for (uint32_t k = 1; k <= parts; ++k) files[k] += fmt::format("\n}} // namespace nesshi::iss::detail::{}\n", id);
    // The tables, with every run declared.
    out = header;
    for (uint32_t r = 0; r < starts.size(); ++r) out += fmt::format("bool run_{}(Core& c);\n", r);
    out += "\nnamespace {\n\nconst CompiledRun kEntry[] = {";
    for (uint32_t pc = 0; pc < nb; ++pc) out += fmt::format("{}run_{}", sep(pc, 8), run_of[pc]);
    out += "};\nconst uint32_t kRunOf[] = {";
    for (uint32_t pc = 0; pc < nb; ++pc) out += fmt::format("{}{}", sep(pc, 16), run_of[pc]);
    out += fmt::format("}};\n\n}} // namespace\n}} // namespace nesshi::iss::detail::{}\n\n", id);
    out += fmt::format("namespace nesshi::machine::detail {{\nextern const iss::CompiledProgram kCompiled_{};\n"
                       "const iss::CompiledProgram kCompiled_{} = {{\"{}\", 0x{:016x}ull, {}, iss::detail::{}::kEntry, "
                       "iss::detail::{}::kRunOf, {}}};\n}} // namespace nesshi::machine::detail\n",
                       id, id, spec, prog.decoded_hash(), nb, id, id, starts.size());
    files[0] = std::move(out);
    return files;
}

void write_if_changed(const std::string& path, const std::string& text) {
    std::ifstream in(path, std::ios::binary);
    std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in && old == text) return;
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s OUTDIR KERNEL@MACHINE...\n", argv[0]);
        return 2;
    }
    try {
        const std::string dir = argv[1];
        const kernels::SourceSet src = kernels::embedded();
        std::string reg = "// Generated by nesshi_gen_compiled_runs; do not edit.\n#include \"compiled_runs.hpp\"\n"
                          "#include \"iss/compiled.hpp\"\n\n#include <mutex>\n\nnamespace nesshi::machine::detail {\n";
        std::string body;
        for (int i = 2; i < argc; ++i) {
            std::string spec = argv[i];
            uint32_t parts = 1;
            if (const size_t colon = spec.rfind(':'); colon != std::string::npos) {
                parts = static_cast<uint32_t>(std::stoul(spec.substr(colon + 1)));
                spec.resize(colon);
            }
            const size_t at = spec.find('@');
            if (at == std::string::npos || parts == 0) throw std::runtime_error("not KERNEL@MACHINE[:PARTS]: " + spec);
            const std::string kernel = spec.substr(0, at), mach = spec.substr(at + 1);
            const auto prog = kernel.ends_with(".pk") ? machine::assemble_source(src, kernel, mach)
                                                      : machine::assemble_kernel(src, kernel, mach);
            const std::string id = ident(spec);
            const std::vector<std::string> files = program_code(*prog, spec, id, parts);
            write_if_changed(dir + "/" + id + ".cpp", files[0]);
            for (uint32_t k = 1; k < files.size(); ++k)
                write_if_changed(fmt::format("{}/{}_{}.cpp", dir, id, k - 1), files[k]);
            reg += fmt::format("extern const iss::CompiledProgram kCompiled_{};\n", id);
            body += fmt::format("        iss::register_compiled(kCompiled_{});\n", id);
        }
        reg += "\nvoid register_compiled_runs() {\n    static std::once_flag once;\n    std::call_once(once, [] {\n" + body +
               "    });\n}\n\n} // namespace nesshi::machine::detail\n";
        write_if_changed(dir + "/register.cpp", reg);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "nesshi_gen_compiled_runs: %s\n", e.what());
        return 1;
    }
    return 0;
}
