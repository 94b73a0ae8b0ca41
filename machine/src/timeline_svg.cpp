// `nesshi render --timeline-svg FILE`: a render's run as a picture, beside the Perfetto trace of
// --trace: over the machine's cycles (in 240 bins), each stage's busy fraction (processing and
// communication; the rest is waiting), the mean over PEs; below it, each FIFO's words, the most
// any PE held in the bin. Lines differ by dash as well as colour.
#include "pe.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::machine {
namespace {

constexpr int kBins = 240, kLeft = 70, kPlotW = 720, kPanelH = 170, kTop = 50, kGap = 70, kLegendW = 230;
constexpr const char* kColours[] = {"#0072B2", "#E69F00", "#009E73", "#D55E00"};
constexpr const char* kDashes[] = {"", "7 3", "2 3", "9 3 2 3"};

std::string polyline(const std::vector<double>& v, double top, int y0, int k) {
    std::string pts;
    for (std::size_t i = 0; i < v.size(); ++i)
        pts += fmt::format("{}{:.1f},{:.1f}", i ? " " : "", kLeft + kPlotW * (static_cast<double>(i) + 0.5) / static_cast<double>(v.size()),
                           y0 + kPanelH * (1 - (top > 0 ? v[i] / top : 0)));
    return fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"{}/>\n", pts, kColours[k],
                       *kDashes[k] ? fmt::format(" stroke-dasharray=\"{}\"", kDashes[k]) : "");
}

// A panel's frame, y ticks, title and legend.
std::string panel(int y0, const std::string& title, const std::vector<std::string>& ticks,
                  const std::vector<std::string>& names) {
    std::string o = fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"13\" font-weight=\"bold\">{}</text>\n", kLeft, y0 - 10, title);
    for (std::size_t i = 0; i < ticks.size(); ++i) {
        const double y = y0 + kPanelH * (1 - static_cast<double>(i) / static_cast<double>(ticks.size() - 1));
        o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#e5e5e5\"/>\n", kLeft, kLeft + kPlotW, y, y);
        o += fmt::format("<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n", kLeft - 6, y + 4, ticks[i]);
    }
    o += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\n", kLeft, y0, kPlotW, kPanelH);
    for (std::size_t k = 0; k < names.size(); ++k) {
        const int lx = kLeft + kPlotW + 20, ly = y0 + 14 + 20 * static_cast<int>(k);
        o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"2\"{}/>\n", lx, lx + 30, ly - 4,
                         ly - 4, kColours[k], *kDashes[k] ? fmt::format(" stroke-dasharray=\"{}\"", kDashes[k]) : "");
        o += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", lx + 38, ly, names[k]);
    }
    return o;
}

} // namespace

std::string timeline_svg(const std::vector<PeResult>& pes) {
    std::uint64_t end = 1;
    for (const PeResult& p : pes) end = std::max(end, p.end);
    const int bins = static_cast<int>(std::min<std::uint64_t>(kBins, end));
    const double width = static_cast<double>(end) / bins; // cycles per bin
    auto bin_start = [&](int b) { return static_cast<std::uint64_t>(std::llround(b * width)); };

    // Busy cycles per stage and bin, summed over PEs, from the activity stretches (each spread
    // evenly over its stretch: the order of its kinds inside is not known).
    std::vector<std::vector<double>> busy(3, std::vector<double>(static_cast<std::size_t>(bins), 0));
    std::vector<std::vector<double>> words(4, std::vector<double>(static_cast<std::size_t>(bins), 0));
    for (const PeResult& p : pes) {
        for (int k = 0; k < 3; ++k)
            for (const Activity& a : p.activity[static_cast<std::size_t>(k)]) {
                if (a.end <= a.start) continue;
                const double rate = static_cast<double>(a.processing + a.communication) / static_cast<double>(a.end - a.start);
                for (int b = static_cast<int>(static_cast<double>(a.start) / width); b < bins && bin_start(b) < a.end; ++b) {
                    const std::uint64_t lo = std::max(a.start, bin_start(b)), hi = std::min(a.end, bin_start(b + 1));
                    if (hi > lo) busy[static_cast<std::size_t>(k)][static_cast<std::size_t>(b)] += rate * static_cast<double>(hi - lo);
                }
            }
        std::uint32_t last[4] = {0, 0, 0, 0};
        std::size_t i = 0;
        for (int b = 0; b < bins; ++b) {
            std::uint32_t most[4] = {last[0], last[1], last[2], last[3]};
            for (; i < p.samples.size() && p.samples[i].cycle < bin_start(b + 1); ++i)
                for (int f = 0; f < 4; ++f) {
                    last[f] = p.samples[i].fifo[f];
                    most[f] = std::max(most[f], last[f]);
                }
            for (int f = 0; f < 4; ++f)
                words[static_cast<std::size_t>(f)][static_cast<std::size_t>(b)] =
                    std::max(words[static_cast<std::size_t>(f)][static_cast<std::size_t>(b)], static_cast<double>(most[f]));
        }
    }
    for (auto& stage : busy)
        for (int b = 0; b < bins; ++b)
            stage[static_cast<std::size_t>(b)] /= static_cast<double>(bin_start(b + 1) - bin_start(b)) * static_cast<double>(pes.size());
    double most_words = 1;
    for (const auto& f : words) most_words = std::max(most_words, *std::max_element(f.begin(), f.end()));
    double words_top = 1; // the 1-2-5 value at or above the most words
    for (double d = 1; words_top < most_words; d *= 10)
        for (double m : {1.0, 2.0, 5.0, 10.0})
            if (words_top < most_words) words_top = d * m;

    const int second = kTop + kPanelH + kGap;
    const int height = second + kPanelH + 60;
    const int total_w = kLeft + kPlotW + kLegendW;
    std::string o = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
                                "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
                                "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
                                total_w, height);
    o += fmt::format("<text x=\"{}\" y=\"20\" font-size=\"15\">The run over time: {} cycles, {} PE{}</text>\n", kLeft, end, pes.size(),
                     pes.size() == 1 ? "" : "s");
    o += panel(kTop, fmt::format("stage busy (processing + communication){}", pes.size() > 1 ? ", mean over PEs" : ""),
               {"0", "25%", "50%", "75%", "100%"}, {"OS", "IC", "SC (modelled)"});
    for (int k = 0; k < 3; ++k) o += polyline(busy[static_cast<std::size_t>(k)], 1, kTop, k);
    std::vector<std::string> word_ticks;
    for (int i = 0; i <= 4; ++i) word_ticks.push_back(fmt::format("{:g}", words_top * i / 4));
    o += panel(second, fmt::format("FIFO words{}", pes.size() > 1 ? ", the most a PE held" : ""), word_ticks,
               {"OS in (DIS, SC, IC)", "IC in (OS)", "SC in (OS)", "SC in (IC)"});
    for (int f = 0; f < 4; ++f) o += polyline(words[static_cast<std::size_t>(f)], words_top, second, f);
    // The cycle axis, under both panels.
    const double unit = end >= 2'000'000 ? 1e6 : end >= 2000 ? 1e3 : 1;
    for (int i = 0; i <= 5; ++i) {
        const double x = kLeft + kPlotW * i / 5.0;
        for (int y0 : {kTop, second})
            o += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{:.3g}</text>\n", x, y0 + kPanelH + 16,
                             static_cast<double>(end) * i / 5.0 / unit);
    }
    o += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">cycles{}</text>\n", kLeft + kPlotW / 2, second + kPanelH + 36,
                     unit == 1e6 ? " (millions)" : unit == 1e3 ? " (thousands)" : "");
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::machine
