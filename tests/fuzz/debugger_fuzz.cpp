// Fuzz target `debugger`: the input is a debugger script, one command per line, run through
// Debugger::execute on each of three small programs (exposed latencies, FIFO words, a loop).
// Any command line gives a message or a result, never a crash.
#include "assembler/assembler.hpp"
#include "iss/channel.hpp"
#include "iss/debugger.hpp"
#include "iss/processor.hpp"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

using namespace nesshi;

namespace {

std::vector<std::shared_ptr<const iss::Program>> programs() {
    std::vector<std::shared_ptr<const iss::Program>> v;
    for (const char* rel : {"tests/iss/programs/latency.s", "examples/fifo_echo.s", "examples/dot3.s"}) {
        const std::string path = std::string(NESSHI_SOURCE_DIR) + "/" + rel;
        const isa::Machine m = isa::load_machine("os");
        const assembler::AsmResult r = assembler::assemble_file(path, m, {});
        if (!r.ok) throw std::runtime_error(path + ":\n" + r.diagnostics);
        v.push_back(iss::load_program(r.object, m));
    }
    return v;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const auto progs = programs();
    static std::FILE* sink = std::fopen("/dev/null", "w");
    const std::string_view script(reinterpret_cast<const char*>(data), size);
    for (const auto& prog : progs) {
        iss::Processor p(prog, iss::Engine::Checked);
        iss::QueueChannel in, out;
        for (std::uint32_t w : {3u, 10u, 20u, 30u}) in.feed(w);
        in.close();
        p.attach_channel(0, &in);
        p.attach_channel(1, &out);
        iss::Debugger d(p, sink);
        d.max_cycles = 5'000;
        std::size_t at = 0;
        for (int lines = 0; at <= script.size() && lines < 64; ++lines) {
            const std::size_t nl = script.find('\n', at);
            const std::string_view line = script.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
            if (!d.execute(line)) break;
            if (nl == std::string_view::npos) break;
            at = nl + 1;
        }
    }
    return 0;
}
