// The benchmarks' one command-line rule: `--NAME VALUE` options from a fixed list, `-h`/`--help`
// prints the usage and exits 0 (never starts a benchmark), anything else prints it and exits 2.
//
//   const bench::Args a = bench::parse_args(argc, argv, "usage: bench_sched [--loops N]", {"--loops"});
//   const int loops = a.number("--loops", 200);
#pragma once

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace nesshi::bench {

struct Args {
    std::map<std::string, std::string> values; // by option name, the last value given
    std::vector<std::string> positionals;      // when the caller takes them
    std::string text(const std::string& name, const std::string& fallback) const {
        const auto it = values.find(name);
        return it == values.end() ? fallback : it->second;
    }
    long number(const std::string& name, long fallback) const {
        const auto it = values.find(name);
        if (it == values.end()) return fallback;
        char* end = nullptr;
        const long v = std::strtol(it->second.c_str(), &end, 10);
        if (it->second.empty() || *end != '\0') {
            std::fprintf(stderr, "%s takes a whole number, not '%s'\n", name.c_str(), it->second.c_str());
            std::exit(2);
        }
        return v;
    }
};

inline Args parse_args(int argc, char** argv, const char* usage, const std::vector<std::string>& options,
                       bool take_positionals = false) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "-h" || arg == "--help") {
            std::printf("%s\n", usage);
            std::exit(0);
        }
        bool known = false;
        for (const std::string& o : options) known |= o == arg;
        if (known && i + 1 < argc) {
            a.values[arg] = argv[++i];
        } else if (!known && take_positionals && arg.rfind("-", 0) != 0) {
            a.positionals.push_back(arg);
        } else {
            std::fprintf(stderr, "%s: %s\n%s\n", argv[0], known ? ("no value after " + arg).c_str() : ("unknown argument '" + arg + "'").c_str(), usage);
            std::exit(2);
        }
    }
    return a;
}

} // namespace nesshi::bench
