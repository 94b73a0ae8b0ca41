// A stage's machine description, loaded once where it is named (a command-line option, a sweep
// axis, a Python argument) and passed on as a value: every consumer (the kernel build, the SC's
// prices, provenance, the reports) reads the same machine, and none parses it again.
//
//   machine::Options mo;                       // os, ic and seq by default
//   mo.ic_machine = "ic-real";                 // loads the preset (or a .toml file) now
//   mo.ic_machine = kbuild::StageMachine(m, "my-ic");  // a machine built in memory
//   mo.ic_machine.same_as_preset("ic")         // identity by fingerprint, whatever its name
#pragma once
#include "isa/machine.hpp"

#include <string>
#include <string_view>

namespace nesshi::kbuild {

class StageMachine {
  public:
    // Loads a preset's name or a .toml file's path (throws as isa::load_machine: a clear error
    // naming the file and line).
    StageMachine(std::string_view name_or_path); // NOLINT: implicit, so that an option's text assigns
    StageMachine(const char* name_or_path) : StageMachine(std::string_view(name_or_path)) {}
    StageMachine(const std::string& name_or_path) : StageMachine(std::string_view(name_or_path)) {}
    // A machine already loaded; `reference` says what named it (provenance, messages).
    StageMachine(isa::Machine m, std::string reference) : machine_(std::move(m)), reference_(std::move(reference)) {}

    const isa::Machine& machine() const { return machine_; }
    // What named it: a preset's name or a file's path as given.
    const std::string& reference() const { return reference_; }
    // Whether it is the preset `name` under any name (same fingerprint once named alike).
    bool same_as_preset(std::string_view name) const;

  private:
    isa::Machine machine_;
    std::string reference_;
};

} // namespace nesshi::kbuild
