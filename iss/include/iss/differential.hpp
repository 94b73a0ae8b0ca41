// Differential runs: two programs for one machine, the same random input data, and the first
// difference in what they leave behind (memory of their data sections, named registers).
// `nesshi pipeline --verify` runs a loop's sequential meaning against its pipelined code this way.
//
//   iss::DiffOptions o;  o.registers = {"r1", "f5"};
//   if (auto d = iss::run_differential(linear, pipelined, machine, o)) fmt::print("{}\n", *d);
#pragma once

#include "isa/machine.hpp"
#include "isa/object.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nesshi::iss {

struct DiffOptions {
    std::uint64_t seed = 1;
    bool randomize_data = true;          // every word of the data sections: a random float in [-8, 8)
    std::vector<std::string> registers;  // compared after both halt ("r1", "f5")
    std::uint64_t max_cycles = 10'000'000;
    std::vector<std::string> observe;    // registers of the first program read back, not compared
    std::size_t fifo_words = 4096;       // random words on every channel the programs receive from; what they send is compared
};

// Runs both to halt; returns the first difference ("mem[0x1024]: 3.5 (0x40600000) vs ...",
// "r1: 4104 vs 4108", a fault or a cycle limit of one side), or nothing when they agree.
// `observed` (when given) receives the values of opts.observe in the first program after it halts.
std::optional<std::string> run_differential(const isa::ObjectFile& a, const isa::ObjectFile& b, const isa::Machine& m,
                                            const DiffOptions& opts, std::vector<std::uint32_t>* observed = nullptr);

} // namespace nesshi::iss
