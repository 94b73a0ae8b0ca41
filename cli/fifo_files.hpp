// --fifo-in / --fifo-out [CH=]FILE, shared by `sim` and `debug`: the spec's parse, and the
// check that the program uses the channel at all.
#pragma once

#include "iss/program.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace nesshi::cli {

// "[CH=]FILE" -> (channel, file); the default channel is `def`. A bad channel is a usage error.
std::pair<uint32_t, std::string> channel_spec(const std::string& spec, uint32_t def);

// A FIFO file for a channel the program never uses would change nothing (an input never read,
// an output always empty): a usage error that names the channels it does use. `input` names the
// program in the message.
void check_channels_used(const std::vector<std::string>& fifo_in, const std::vector<std::string>& fifo_out,
                         const std::string& input, const iss::Program& prog);

} // namespace nesshi::cli
