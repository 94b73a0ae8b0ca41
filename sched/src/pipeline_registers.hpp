// Internal to the pipeliner: physical registers for a modulo schedule (modulo variable
// expansion: each virtual register gets as many copies as its lifetime spans IIs, the kernel
// unrolled to rotate them), and the kernel's write-port check around a taken-branch bubble.
#pragma once

#include "pipeline_search.hpp"

#include "isa/machine.hpp"

#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nesshi::sched::pipe {

constexpr int kMaxBubbleUnroll = 8; // kernel copies a while loop may get for its branch bubble
constexpr int kMaxPortUnroll = 16;  // kernel copies any loop may get to keep writes off one port
constexpr int kMaxGroups = 8;        // kernel repeats a counted loop may get for its branch bubble (Allocation::groups)
constexpr int kMaxKernelBundles = 128; // ... while its kernel stays this short

struct Allocation {
    int unroll = 1;
    std::vector<int> copies;                     // per virtual: registers in rotation
    std::vector<std::vector<std::string>> regs;  // per virtual, per copy
    int counter = -1;                            // integer register of the kernel counter
    std::vector<std::string> scratch;
    std::vector<int> lifetime;                   // per virtual, cycles
    int entry_nops = 0;                          // between prologue and kernel (kernel_landings_ok)
    // A counted loop's kernel holds `groups` x `unroll` copies (the registers rotate every
    // `unroll`), each with its exit test: the taken-branch bubble is paid once per pass of them all,
    // with no register more, only code.
    int groups = 1;
};

// The most times a counted loop's kernel pass of `pass` bundles may be repeated: a power of two,
// at most kMaxGroups, the kernel within kMaxKernelBundles (1 when even two passes are longer).
int most_repeats(int pass);
// How many times (a power of two, at most `most`) a kernel pass of `pass` cycles is repeated so
// that a taken-branch bubble of `penalty` cycles is at most a twentieth of the whole: a while
// loop's kernel copies and a counted loop's repeats without .trip follow this one rule.
int bubble_repeats(int penalty, int pass, int most);

Allocation allocate(const Region& r, const Graph& g, const Schedule& s, const std::set<std::pair<int, int>>& named,
                    const isa::Machine& m, std::string_view file, int min_unroll = 1);

// Whether the kernel, `unroll` x `groups` copies of the II rows (a counted loop's each with its
// counter decrement), passes the assembler's write-port check
// when entered both ways: from the prologue (straight, or after `entry_nops` as long as the
// taken-branch bubble) and around its back edge (after the bubble). The reservation table
// counts landings modulo II, which is exact only without a bubble. The assembler checks each
// write against the writes in flight where it is issued, merging the paths into a bundle, so a
// write of the kernel meets those of both ways in; with entry nops both bring the same writes
// (the same registers: the kernel's copies rotate with the prologue's passes) at the same cycles.
// Costs nothing beside assembling the file.
bool kernel_landings_ok(const Graph& g, const Schedule& s, int unroll, int groups, const isa::Machine& m, bool entry_nops);

} // namespace nesshi::sched::pipe
