// The in-memory FIFO and the word-file format of `nesshi sim --fifo-in/--fifo-out`.
#include "iss/channel.hpp"

#include "base/error.hpp"
#include "base/read_file.hpp"

#include <fmt/core.h>

#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace nesshi::iss {

size_t QueueChannel::readable(uint64_t cycle, size_t enough) const {
    size_t n = 0;
    for (const Word& w : words_) {
        if (w.ready > cycle || n == enough) break;
        ++n;
    }
    return n;
}

std::optional<uint64_t> QueueChannel::front_ready() const {
    if (words_.empty()) return std::nullopt;
    return words_.front().ready;
}

uint32_t QueueChannel::pop() {
    if (words_.empty()) return 0; // the engine never pops an empty channel
    uint32_t v = words_.front().value;
    words_.pop_front();
    ++popped_;
    return v;
}

void QueueChannel::push(uint32_t word, uint64_t cycle) {
    words_.push_back({word, cycle + latency_});
    ++pushed_;
}

std::vector<uint32_t> QueueChannel::drain_all() {
    std::vector<uint32_t> out;
    for (const Word& w : words_) out.push_back(w.value);
    words_.clear();
    return out;
}

namespace {
bool parse_token(std::string_view tok, uint32_t& out) {
    bool neg = !tok.empty() && tok[0] == '-';
    std::string_view body = neg || (!tok.empty() && tok[0] == '+') ? tok.substr(1) : tok;
    // One sign at most: "--5" and "+-5" are not numbers (and "--9223372036854775808" overflowed).
    if (body.empty() || body[0] == '-' || body[0] == '+') return false;
    if (body.size() > 2 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X')) {
        uint64_t v = 0;
        auto r = std::from_chars(body.data() + 2, body.data() + body.size(), v, 16);
        if (r.ec != std::errc() || r.ptr != body.data() + body.size() || v > 0xffffffffull) return false;
        out = neg ? uint32_t(0u - uint32_t(v)) : uint32_t(v);
        return true;
    }
    bool is_float = body.find_first_of(".eE") != std::string_view::npos || body == "inf" || body == "nan";
    if (is_float) {
        std::string s(tok);
        char* end = nullptr;
        float f = std::strtof(s.c_str(), &end);
        if (end != s.c_str() + s.size()) return false;
        out = std::bit_cast<uint32_t>(f);
        return true;
    }
    uint64_t v = 0; // the magnitude: no sign left in `body`, so nothing can overflow
    auto r = std::from_chars(body.data(), body.data() + body.size(), v, 10);
    if (r.ec != std::errc() || r.ptr != body.data() + body.size()) return false;
    if (neg ? v > uint64_t{1} << 31 : v > UINT32_MAX) return false; // INT32_MIN..UINT32_MAX
    out = neg ? uint32_t(0u - uint32_t(v)) : uint32_t(v);
    return true;
}
} // namespace

std::vector<uint32_t> parse_words(std::string_view text, std::string_view name) {
    std::vector<uint32_t> out;
    size_t line_no = 0, pos = 0;
    while (pos <= text.size()) {
        size_t nl = text.find('\n', pos);
        std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        ++line_no;
        if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            size_t j = i;
            while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
            if (j > i) {
                uint32_t w;
                if (!parse_token(line.substr(i, j - i), w))
                    throw base::Error(base::SourceLoc(name, int(line_no), int(i + 1)),
                                      fmt::format("bad word '{}'", line.substr(i, j - i)));
                out.push_back(w);
            }
            i = j;
        }
        if (nl == std::string_view::npos) break;
        pos = nl + 1;
    }
    return out;
}

std::vector<uint32_t> read_word_file(const std::string& path) { return parse_words(base::read_file(path), path); }

std::pair<uint32_t, std::string> parse_channel_spec(std::string_view spec, uint32_t default_channel) {
    const size_t eq = spec.find('=');
    if (eq == std::string_view::npos || spec.empty() || !std::isdigit(static_cast<unsigned char>(spec[0])))
        return {default_channel, std::string(spec)};
    const std::string_view ch = spec.substr(0, eq);
    uint64_t v = 0;
    const auto r = std::from_chars(ch.data(), ch.data() + ch.size(), v, 10);
    if (r.ptr != ch.data() + ch.size() || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
        throw std::invalid_argument(fmt::format("bad channel '{}' in '{}' (expected [CH=]FILE, CH a number 0..{})", ch,
                                                spec, UINT32_MAX));
    if (r.ec == std::errc::result_out_of_range || v > UINT32_MAX)
        throw std::invalid_argument(fmt::format("channel {} in '{}' is out of range (0..{})", ch, spec, UINT32_MAX));
    if (eq + 1 == spec.size()) throw std::invalid_argument(fmt::format("no file after '=' in '{}'", spec));
    return {uint32_t(v), std::string(spec.substr(eq + 1))};
}

std::string format_words(const std::vector<uint32_t>& words) {
    std::string out;
    for (uint32_t w : words) {
        float f = std::bit_cast<float>(w);
        std::string fs = std::isfinite(f) ? fmt::format("{}", f) : (std::isnan(f) ? "nan" : (f > 0 ? "inf" : "-inf"));
        out += fmt::format("0x{:08x}  # {} {}\n", w, int32_t(w), fs);
    }
    return out;
}

} // namespace nesshi::iss
