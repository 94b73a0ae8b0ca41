// The fuzz harnesses' one failure: a broken property is printed and aborts, which libFuzzer
// and the replay test both report as a crash.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace nesshi::fuzz {

[[noreturn]] inline void fail(const std::string& what, const std::string& detail = {}) {
    std::fprintf(stderr, "fuzz property broken: %s\n%s\n", what.c_str(), detail.c_str());
    std::abort();
}

inline void check(bool ok, const std::string& what, const std::string& detail = {}) {
    if (!ok) fail(what, detail);
}

} // namespace nesshi::fuzz
