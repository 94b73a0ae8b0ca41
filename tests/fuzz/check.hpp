// The fuzz harnesses' one failure: a broken property is printed and aborts, which libFuzzer
// and the replay test both report as a crash.
#pragma once

#include "bytes.hpp"

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

// `preset` itself, or (when `copy`) a copy of it in `storage` with latencies 1-6 per op class and a
// branch penalty 0-2 read from `in`: a machine no file describes, made without parsing one.
inline const isa::Machine& latency_variant(Bytes& in, const isa::Machine& preset, bool copy, isa::Machine& storage) {
    if (!copy) return preset;
    storage = preset;
    storage.name = "random";
    storage.source = "fuzz-random";
    for (std::uint32_t& l : storage.latency) l = 1 + in.next() % 6;
    storage.branch_penalty = in.next() % 3;
    return storage;
}

} // namespace nesshi::fuzz
