#include "fifo_files.hpp"
#include "errors.hpp"

#include "iss/channel.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <set>
#include <stdexcept>

namespace nesshi::cli {

std::pair<uint32_t, std::string> channel_spec(const std::string& spec, uint32_t def) {
    try {
        return iss::parse_channel_spec(spec, def);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

void check_channels_used(const std::vector<std::string>& fifo_in, const std::vector<std::string>& fifo_out,
                         const std::string& input, const iss::Program& prog) {
    std::set<uint32_t> recv, send;
    for (const auto& d : prog.ops()) {
        const isa::Kind k = d.instr.info().kind;
        if (k == isa::Kind::Recv) recv.insert(d.imm);
        if (k == isa::Kind::Send) send.insert(d.imm);
    }
    auto check = [&](const char* option, const std::string& spec, uint32_t def, const std::set<uint32_t>& used,
                     const char* verb) {
        const uint32_t ch = channel_spec(spec, def).first;
        if (used.count(ch)) return;
        throw UsageError(fmt::format("{} {}: {} never {} on channel {} ({})", option, spec, input, verb, ch,
                                     used.empty() ? fmt::format("it {} on no channel", verb)
                                                  : fmt::format("it {} on {}", verb, fmt::join(used, ", "))));
    };
    for (const auto& spec : fifo_in) check("--fifo-in", spec, 0, recv, "receives");
    for (const auto& spec : fifo_out) check("--fifo-out", spec, 1, send, "sends");
}

} // namespace nesshi::cli
