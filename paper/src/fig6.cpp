// Fig. 6 of the paper as SVG: per scene, bars of models S, M and V at each grid (billions of
// cycles). S is stacked by the stages' loads (its time is their sum); M and V show the total,
// lightly, with the largest stage's load solid and named, since a pipeline's time follows its bottleneck stage.
#include "report_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nesshi::paper {

namespace {

constexpr const char* kStageNames[3] = {"OS", "IC", "SC"};
constexpr const char* kStageColors[3] = {"#4e79a7", "#f28e2b", "#59a14f"};

// Layout (pixels).
constexpr int kBarWidth = 16, kBarGap = 4, kGroupGap = 22, kAxisWidth = 52, kPlotHeight = 230;
constexpr int kPanelTop = 36, kPanelBottom = 44, kPanelsPerRow = 3, kMargin = 16, kHeader = 64, kLegend = 64;

struct Bar {
    machine::Model model;
    double total = 0;               // billions, scaled to 512x512
    std::array<double, 3> stages{}; // loads, billions
    double paper = 0;               // the paper's Table 3 value, billions (0: none)
};

struct Panel {
    std::string scene;
    std::vector<std::pair<int, std::vector<Bar>>> groups; // grid -> bars
    double max = 0;
};

Panel make_panel(const PaperData& d, const std::string& scene) {
    const double k = scale_to_paper(d.size) / 1e9;
    const bool comparable = is_paper_scene_size(scene);
    Panel p{scene, {}, 0};
    for (int g : d.grids) {
        std::vector<Bar> bars;
        const PublishedTimes* pub = comparable ? find_published_times(paper_scene(scene), g) : nullptr;
        for (machine::Model m : d.models) {
            const CellRecord* c = d.find(scene, g, m);
            Bar b{m};
            if (c) {
                b.total = static_cast<double>(m == machine::Model::S ? s_time(*c) : c->total) * k;
                b.stages = {static_cast<double>(c->os.load()) * k, static_cast<double>(c->ic.load()) * k,
                            static_cast<double>(c->sc.load()) * k};
            }
            if (pub) b.paper = (m == machine::Model::S ? pub->s : m == machine::Model::M ? pub->m : pub->v).value / 1e3;
            p.max = std::max({p.max, b.total, b.paper, b.stages[0] + b.stages[1] + b.stages[2]});
            bars.push_back(b);
        }
        p.groups.emplace_back(g, std::move(bars));
    }
    return p;
}

int panel_width(const PaperData& d) {
    const int models = static_cast<int>(d.models.size()), grids = static_cast<int>(d.grids.size());
    const int group = models * kBarWidth + (models - 1) * kBarGap;
    return kAxisWidth + grids * group + (grids + 1) * kGroupGap;
}

std::string rect(double x, double y, double w, double h, const char* fill, double opacity, const std::string& tip) {
    return fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" "
                       "fill-opacity=\"{}\"><title>{}</title></rect>\n",
                       x, y, w, std::max(h, 0.0), fill, opacity, xml_escape(tip));
}

std::string draw_bar(const Bar& b, const std::string& label, double x, double base, double px_per_unit) {
    std::string o;
    const char* model = machine::model_name(b.model);
    if (b.total <= 0) {
        o += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" class=\"small\" text-anchor=\"middle\">—</text>\n",
                         x + kBarWidth / 2.0, base - 4);
    } else if (b.model == machine::Model::S) {
        double y = base;
        for (std::size_t s = 0; s < 3; ++s) {
            const double h = b.stages[s] * px_per_unit;
            y -= h;
            o += rect(x, y, kBarWidth, h, kStageColors[s], 1.0,
                      fmt::format("{} S: {} load {:.4g} of {:.4g} billion cycles", label, kStageNames[s], b.stages[s],
                                  b.total));
        }
    } else {
        const std::size_t top =
            static_cast<std::size_t>(std::max_element(b.stages.begin(), b.stages.end()) - b.stages.begin());
        const std::string tip = fmt::format("{} {}: {:.4g} billion cycles, largest stage {} (load {:.4g})", label,
                                            model, b.total, kStageNames[top], b.stages[top]);
        o += rect(x, base - b.total * px_per_unit, kBarWidth, b.total * px_per_unit, kStageColors[top], 0.35, tip);
        o += rect(x, base - b.stages[top] * px_per_unit, kBarWidth, b.stages[top] * px_per_unit, kStageColors[top], 1.0,
                  tip);
        o +=
            fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" class=\"tiny\" text-anchor=\"middle\" fill=\"{}\">{}</text>\n",
                        x + kBarWidth / 2.0, base - b.total * px_per_unit - 3, kStageColors[top], kStageNames[top]);
    }
    if (b.paper > 0) {
        const double y = base - b.paper * px_per_unit;
        o += fmt::format(
            "<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" class=\"paper\"><title>{}</title></line>\n",
            x - 2, x + kBarWidth + 2, y, y,
            xml_escape(fmt::format("{} {}: paper {:.4g} billion cycles", label, model, b.paper)));
    }
    o += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" class=\"small\" text-anchor=\"middle\">{}</text>\n",
                     x + kBarWidth / 2.0, base + 12, model);
    return o;
}

std::string draw_panel(const PaperData& d, const Panel& p, int left, int top) {
    const double step = axis_step(p.max), axis_max = std::max(step, std::ceil(p.max / step - 1e-9) * step);
    const double px = kPlotHeight / axis_max;
    const int plot_left = left + kAxisWidth, width = panel_width(d) - kAxisWidth;
    const double base = top + kPanelTop + kPlotHeight;
    std::string o =
        fmt::format("<text x=\"{}\" y=\"{}\" class=\"panel\">{}</text>\n", plot_left, top + 20, xml_escape(p.scene));
    for (double v = 0; v <= axis_max * (1 + 1e-9); v += step) {
        const double y = base - v * px;
        o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" class=\"grid\"/>\n", plot_left,
                         plot_left + width, y, y);
        o += fmt::format("<text x=\"{}\" y=\"{:.1f}\" class=\"small\" text-anchor=\"end\">{:g}</text>\n", plot_left - 4,
                         y + 3, v);
    }
    int x = plot_left + kGroupGap;
    for (const auto& [grid, bars] : p.groups) {
        const int group_width = static_cast<int>(bars.size()) * (kBarWidth + kBarGap) - kBarGap;
        for (std::size_t i = 0; i < bars.size(); ++i)
            o += draw_bar(bars[i], fmt::format("{} grid {}", p.scene, grid),
                          x + static_cast<double>(i) * (kBarWidth + kBarGap), base, px);
        o += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" class=\"label\" text-anchor=\"middle\">{}</text>\n",
                         x + group_width / 2.0, base + 28, grid);
        x += group_width + kGroupGap;
    }
    o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" class=\"axis\"/>\n", plot_left,
                     plot_left + width, base, base);
    o += fmt::format("<text x=\"{}\" y=\"{:.1f}\" class=\"small\">grid</text>\n", plot_left + width - 22, base + 40);
    return o;
}

std::string legend(int x, int y) {
    std::string o;
    for (std::size_t s = 0; s < 3; ++s) {
        o += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"{}\"/>", x, y, kStageColors[s]);
        o += fmt::format("<text x=\"{}\" y=\"{}\" class=\"label\">{}</text>\n", x + 16, y + 10, kStageNames[s]);
        x += 50;
    }
    o += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\" class=\"paper\"/>", x, x + 16, y + 6, y + 6);
    o += fmt::format("<text x=\"{}\" y=\"{}\" class=\"label\">paper (Table 3)</text>\n", x + 22, y + 10);
    const int left = x - 3 * 50;
    o += fmt::format("<text x=\"{}\" y=\"{}\" class=\"small\">S: stacked by the stages' loads (processing + "
                     "communication).</text>\n",
                     left, y + 30);
    o += fmt::format("<text x=\"{}\" y=\"{}\" class=\"small\">M, V: total (light) with the largest stage's load solid, "
                     "named above the bar.</text>\n",
                     left, y + 44);
    return o;
}

} // namespace

std::string fig6_svg(const PaperData& d) {
    const int pw = panel_width(d), ph = kPanelTop + kPlotHeight + kPanelBottom;
    const int n = static_cast<int>(d.scenes.size()), cols = std::min(n, kPanelsPerRow), rows = (n + cols - 1) / cols;
    const int width = std::max(2 * kMargin + cols * pw, 640), height = kHeader + rows * ph + kLegend + kMargin;
    std::string o = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 "
                                "{0} {1}\" font-family=\"sans-serif\">\n",
                                width, height);
    o += "<style>.title{font-size:16px;font-weight:bold}.panel{font-size:14px;font-weight:bold}"
         ".label{font-size:12px}.small{font-size:10px;fill:#333}.tiny{font-size:8px;font-weight:bold}"
         ".grid{stroke:#ddd;stroke-width:1}.axis{stroke:#333;stroke-width:1}.paper{stroke:#000;stroke-width:2}"
         "</style>\n";
    o += fmt::format("<rect width=\"{}\" height=\"{}\" fill=\"white\"/>\n", width, height);
    std::vector<std::string> models;
    for (machine::Model m : d.models) models.push_back(machine::model_name(m));
    o += fmt::format("<text x=\"{}\" y=\"24\" class=\"title\">Fig. 6 re-run: ray-tracing time of models {} (billions "
                     "of cycles)</text>\n",
                     kMargin, fmt::join(models, ", "));
    const std::string sub =
        d.size == 512
            ? "512x512, one PE"
            : fmt::format(
                  "rendered at {0}x{0}, one PE; scaled by (512/{0})² = {1:g} to compare with the paper's 512x512",
                  d.size, scale_to_paper(d.size));
    o += fmt::format("<text x=\"{}\" y=\"44\" class=\"label\">{}</text>\n", kMargin, xml_escape(sub));
    for (int i = 0; i < n; ++i)
        o += draw_panel(d, make_panel(d, d.scenes[static_cast<std::size_t>(i)]), kMargin + (i % cols) * pw,
                        kHeader + (i / cols) * ph);
    o += legend(kMargin + kAxisWidth, kHeader + rows * ph + 4);
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::paper
