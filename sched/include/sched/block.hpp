// List scheduling of straight-line blocks: the `#pack begin` ... `#pack end` regions of an
// assembly file, written one operation per line in sequential order, become bundles that obey
// the machine's issue slots, register-file ports and exposed latencies; everything outside the
// regions is copied unchanged. `nesshi schedule FILE -m MACHINE` runs it; the kernels' setup,
// VISIT and resume blocks and the IC kernel's primitive bodies come from it (kernels/tools/build.sh).
//
// Virtual registers: a block may name values `%name` (integer or float, by the operand); a
// `#pack virtual f71-f127` line (one range per register file, for the blocks after it) gives the
// registers they take. Before scheduling, each block's are placed by linear scan in program
// order: a last read frees a register to the back of the free list, a result takes the front.
// The range belongs to the tool (the blocks must not name its registers); a value lives inside
// one block.
//
//   const sched::PackResult r = sched::pack_source(text, "dda.pk", isa::load_machine("os"));
//   write(r.text);                       // assembly, the blocks bundled
//   for (const auto& b : r.blocks) ...   // line, ops and bundles of each block
//
// The schedule is critical-path list scheduling, cycle by cycle: an op is ready when every dependence is met
// (true: the producer's latency; anti: a reader issues no later than the overwriting producer
// lands, i.e. distance 1 - latency; output: writes land in order; memory: loads and stores keep
// their order except load/load; FIFO words of a channel keep their order; a branch or halt waits
// for every earlier op to land and stays last; an unconditional jump lets them land during its
// taken-branch bubble, when nothing issues). Among ready ops the one with the longest path to
// the block's end goes first; ops that only the integer units accept are also ranked by how many
// of them follow, since those units are the scarce ones. Slots come from the machine description
// (in a bundle with FIFO words, in program order, because the ISS moves a bundle's words in slot
// order); read ports are counted per bundle and write ports per landing cycle. A block assumes
// that every result of the code before it has landed (the assembler reports it when not).
#pragma once

#include "assembler/assembler.hpp"
#include "isa/encoding.hpp"
#include "isa/machine.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::sched {

// The bundles of one block: op indices, each bundle in program order; an empty bundle is a nop.
std::vector<std::vector<int>> list_schedule(const isa::Machine& m, std::span<const isa::Instr> ops);

// The list schedule shortened by a constraint model (Gecode, the pipeliner's --exact model with
// one pass): a block one bundle shorter than the best so far, while the search finds one within
// `node_budget` nodes (a budget, not a time, so every host builds the same code; 0 keeps the list
// schedule). The model's propagation alone refutes lengths below `fewest`: a block of that many
// bundles is proven shortest. pack_source uses it with kBlockSearchNodes.
struct BlockSchedule {
    std::vector<std::vector<int>> bundles;
    int list_bundles = 0; // the list schedule's length
    int fewest = 0;       // no schedule is shorter (the dependences, then the model's refutations)
    bool shortest() const { return static_cast<int>(bundles.size()) <= fewest; }
};
BlockSchedule block_schedule(const isa::Machine& m, std::span<const isa::Instr> ops, std::uint64_t node_budget);
inline constexpr std::uint64_t kBlockSearchNodes = 300;

// Slots for one bundle's ops (in program order) with FIFO words, and writes of one register, in
// ascending slot order: the first such assignment in lexicographic order, or empty when none exists.
std::vector<int> ordered_slots(const isa::Machine& m, std::span<const isa::Instr> ops);

struct BlockStats {
    int line = 0;    // of its `#pack begin`
    int ops = 0;
    int bundles = 0; // nops included
    int list_bundles = 0;  // before the constraint model shortened it
    int fewest = 0;        // no schedule of the block's ops is shorter
    bool shortest = false; // bundles == fewest
};

struct PackResult {
    std::string text;
    std::vector<BlockStats> blocks;
};

// Throws base::Error (with the file's location) when the file does not assemble with its blocks
// written sequentially, or a block is not closed.
// `opts` says where .include files are found (include_dirs, or read_file for embedded sources).
PackResult pack_source(std::string_view text, std::string_view filename, const isa::Machine& m,
                       const assembler::AsmOptions& opts = {});

// Lines written once and instantiated with names exchanged: the lines between `#copy begin NAME`
// and `#copy end` stay where they are, and each `#copy NAME: X = Y, ...` line appends a copy of
// them after the file's last line (so no line written in the file changes its number), in which
// every whole word X of the code (not of comments) becomes Y and every Y becomes X. A swap is two
// words (r10 = r11), two register ranges of one length (f30-f46 = f50-f66, paired in order) or two
// suffixes (*_A = *_B: tri1_A <-> tri1_B); %virtual registers are never swapped. The IC kernel's
// B bodies are its A bodies with the payload buffers exchanged this way. Marker lines become
// blank. pack_source and machine_sections expand them first. Throws base::Error on a malformed
// line, a block never closed, or a copy of a block not closed before it.
std::string expand_copies(std::string_view text, std::string_view filename);

// Where the lines a `#copy` appended to `text` come from, for diagnostics about its expansion.
class CopiedLines {
  public:
    CopiedLines(std::string_view text, std::string_view filename);
    struct Origin {
        int line = 0;     // the written line it copies
        std::string copy; // the block's name
        int copy_line = 0; // of the `#copy NAME:` line
        std::string note() const; // " [in the copy made by '#copy NAME' at line N]"
    };
    // Line `line` of the expansion when a copy appended it; none for a line written in the file.
    std::optional<Origin> operator()(int line) const;
    // `diagnostics` with each "FILE:L:" of an appended line as the written line, and the note.
    std::string named(const std::string& diagnostics) const;

  private:
    struct Span {
        int at = 0, first = 0, count = 0; // the copy's header comment line; its lines follow
        std::string name;
        int line = 0;
    };
    std::string filename_;
    std::vector<Span> spans_;
};

// Code for one preset only: lines between `#if machine NAME` and `#else` (or `#endif`) are kept
// when m is the preset NAME (same description), the lines between `#else` and `#endif` when it is
// not; the marker lines go. The OS kernel keeps its hand-scheduled voxel loop for `os` this way
// and a `.pipeline while` region, scheduled per machine, for every other one (kernels/os/dda.pk).
// Sections do not nest. Returns, per line of `lines`, whether it stays; pack_source drops the
// others, and machine_sections(text, ...) blanks them (line numbers kept for diagnostics) after
// expanding the text's #copy lines (expand_copies).
std::vector<bool> machine_lines(const std::vector<std::string>& lines, std::string_view filename, const isa::Machine& m);
std::string machine_sections(std::string_view text, std::string_view filename, const isa::Machine& m);

} // namespace nesshi::sched
