// Progress reporting for long runs: a bar redrawn in place on a terminal, and durations.
//
//   mo.progress = base::ProgressBar(stderr);        // "\r[##########          ]  25% " ... "\n" at the end
//   fmt::print("{} left", base::format_duration(s)); // "4:05", "1:02:03"
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace nesshi::base {

// "[####      ]": `percent` (0..100) of `width` cells filled.
inline std::string progress_bar(int percent, int width) {
    const int filled = percent * width / 100;
    return "[" + std::string(static_cast<std::size_t>(filled), '#') +
           std::string(static_cast<std::size_t>(width > filled ? width - filled : 0), ' ') + "]";
}

// Wall seconds since `t0`, for the durations progress reports.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// "m:ss" under an hour, else "h:mm:ss".
inline std::string format_duration(double seconds) {
    const long s = std::lround(seconds);
    char buf[32];
    if (s >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
    return buf;
}

// A bar of `width` cells and the percentage, redrawn in place on `out` at each call with
// (done, total); the line ends when done reaches total.
class ProgressBar {
  public:
    explicit ProgressBar(std::FILE* out, int width = 40) : out_(out), width_(width) {}
    void operator()(std::uint64_t done, std::uint64_t total) const {
        const std::uint64_t pct = total ? done * 100 / total : 100;
        std::fprintf(out_, "\r%s %3d%% ", progress_bar(static_cast<int>(pct), width_).c_str(), static_cast<int>(pct));
        if (done == total) std::fputc('\n', out_);
    }

  private:
    std::FILE* out_;
    int width_;
};

} // namespace nesshi::base
