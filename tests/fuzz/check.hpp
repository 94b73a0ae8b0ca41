// The fuzz harnesses' one failure: a broken property is printed and aborts, which libFuzzer
// and the replay test both report as a crash.
#pragma once

#include "isa/machine.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace nesshi::fuzz {

[[noreturn]] inline void fail(const std::string& what, const std::string& detail = {}) {
    std::fprintf(stderr, "fuzz property broken: %s\n%s\n", what.c_str(), detail.c_str());
    std::abort();
}

inline void check(bool ok, const std::string& what, const std::string& detail = {}) {
    if (!ok) fail(what, detail);
}

// Every preset machine, loaded once.
inline const std::vector<isa::Machine>& presets() {
    static const std::vector<isa::Machine> all = [] {
        std::vector<isa::Machine> v;
        for (std::string_view n : isa::preset_names()) v.push_back(isa::load_machine(n));
        return v;
    }();
    return all;
}

} // namespace nesshi::fuzz
