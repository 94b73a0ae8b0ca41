// Internal to the pipeliner (pipeline.cpp): a `.pipeline` region of linear assembly as parsed,
// its virtual registers and directives, and the text of one of its operations with registers
// and offset filled in.
#pragma once

#include "trip.hpp"

#include "base/error.hpp"
#include "isa/machine.hpp"

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nesshi::sched::pipe {


[[noreturn]] void fail(std::string_view file, int line, const std::string& msg);

// A schedule whose copies of the virtual registers do not fit the register files: that schedule
// fails, not the search (another op order or a larger II has shorter lifetimes).
class RegisterPressure : public base::Error {
  public:
    using base::Error::Error;
};


char file_prefix(isa::RegFile f);
std::string reg_name(isa::RegFile f, int r);

// ---- the region -------------------------------------------------------------------------------

struct SrcOp {
    int line = 0;
    std::string mnemonic;
    std::vector<std::string> operands; // as written, trimmed
    isa::Opcode opcode = 0;
};

struct Virtual {
    std::string name;
    isa::RegFile file = isa::RegFile::Int;
    int def = -1; // the op defining it
};

// The placeholder registers (file, register) of one op's operands and the virtual each stands for.
using OpVirtuals = std::map<std::pair<int, int>, int>;

struct Region {
    std::size_t begin = 0, end = 0; // line indices of .pipeline and .endpipeline
    std::string trip;               // the trip-count register, "r9"
    int trip_reg = 0;
    std::vector<SrcOp> ops;
    std::vector<Virtual> virtuals;
    std::map<std::string, int> virtual_index;
    std::vector<std::pair<int, int>> noalias; // int register pairs
    // `.pipeline while`: no trip count; the one exit test is the conditional branch to `exit`.
    bool is_while = false;
    int exit_op = -1;
    std::set<int> speculate; // `.speculate rA`: loads based on rA may run ahead of the exit
    std::set<std::string> speculate_virtual; // `.speculate %p`: loads based on the virtual %p too
    // `.carry %v, IN[, OUT[, OLD]]`: %v is carried from one iteration to the next (read before its
    // write), starts as IN, ends in OUT (default IN) and, in OLD, the value the exiting iteration
    // started with. `.liveout %v, REG`: the exiting iteration's %v ends in REG.
    struct Carry {
        std::string in, out, old;
    };
    std::map<std::string, Carry> carry;
    std::map<std::string, std::string> liveout;
    int line_of_directives = 0, line_of_speculate = 0;
    TripDirective trip_count; // `.trip MIN[, EXPECTED]` (counted loops)
};


bool opens_region(const std::string& code);

using Span = std::pair<std::size_t, std::size_t>;
std::vector<Span> region_spans(const std::vector<std::string>& lines, std::string_view file);

Region parse_region(const std::vector<std::string>& lines, std::string_view file, Span span);

// Registers the source names anywhere outside comments (never allocated by the tool).
std::set<std::pair<int, int>> named_registers(const std::vector<std::string>& lines);

// The first register the file names that m does not have, reported as the assembler would (line,
// caret), before virtual registers are placed, which would only find too few free ones.
void check_named_in_range(const std::vector<std::string>& lines, std::string_view filename, const isa::Machine& m);

// The op's source text with virtual registers replaced and the memory offset moved by `delta`.
// `prev` (with the op's index): the registers of the previous iteration, which a read of a
// carried virtual register before its write in the body sees.
std::string op_text(const SrcOp& op, const Region& r, const std::vector<std::string>& vreg, std::int64_t delta,
                    const std::vector<std::string>* prev = nullptr, int index = -1);

} // namespace nesshi::sched::pipe
