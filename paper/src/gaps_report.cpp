// The gap attribution as Markdown tables, JSON and CSV (one source of numbers: the GapRow fields).
#include "paper/gaps.hpp"
#include "paper/paper.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>

namespace nesshi::paper {

namespace {

std::string mc(double cycles) { return format_mcycles(cycles); }
std::string fx(double f) { return fmt::format("{:.2f}", f); }
std::string mn(double n) { return fmt::format("{:.3g}", n / 1e6); } // millions of events

const HypothesisResult* find(const GapRow& r, std::string_view name) {
    for (const HypothesisResult& h : r.hypotheses)
        if (h.name == name) return &h;
    return nullptr;
}

struct Stage {
    const char* name;
    double paper, ours, kernel, priced, explained;
    const std::optional<std::string>& adopted;
};

std::array<Stage, 2> stages(const GapRow& r) {
    return {Stage{"OS", r.paper_os, r.ours.os, r.os_kernel, r.os_priced, r.os_explained, r.os_adopted},
            Stage{"IC", r.paper_ic, r.ours.ic, r.ic_kernel, r.ic_priced, r.ic_explained, r.ic_adopted}};
}

std::string counts_table(std::span<const GapRow> rows) {
    std::string o = "| scene | grid | voxel steps: ours | paper | paper/ours | VISITs: ours | paper | paper/ours | "
                    "tests: ours | of which two roots | paper | paper/ours |\n"
                    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const GapRow& r : rows) {
        const WorkCounts& w = r.ours.counts;
        const double tests = w.triangle_tests + w.quadric_tests;
        o += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.scene, r.grid, mn(w.steps),
                         mn(r.implied_steps), fx(r.implied_steps / w.steps), mn(w.visits), mn(r.implied_visits),
                         fx(r.implied_visits / w.visits), mn(tests), mn(w.quadric_two_roots), mn(r.implied_tests),
                         fx(r.implied_tests / tests));
    }
    return o;
}

std::string attribution_table(std::span<const GapRow> rows) {
    std::string o = "| scene | grid | stage | paper | ours | paper/ours | kernel | workload at SPD view | adopted hypothesis "
                    "| its factor | unexplained |\n|---|---:|---|---:|---:|---:|---:|---:|---|---:|---:|\n";
    for (const GapRow& r : rows)
        for (const Stage& s : stages(r))
            o += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.scene, r.grid, s.name,
                             mc(s.paper), mc(s.ours), fx(s.paper / s.ours), fx(s.kernel), fx(s.paper / s.priced),
                             s.adopted ? *s.adopted : "none", fx(s.explained / s.priced), fx(s.paper / s.explained));
    return o;
}

std::string hypotheses_table(std::span<const GapRow> rows) {
    std::vector<std::string> names;
    for (const GapRow& r : rows)
        for (const HypothesisResult& h : r.hypotheses)
            if (std::find(names.begin(), names.end(), h.name) == names.end()) names.push_back(h.name);
    std::string o = "| scene | grid | paper / SPD view: OS | IC |";
    std::string rule = "|---|---:|---:|---:|";
    for (const std::string& n : names) {
        o += fmt::format(" paper / {}: OS | IC |", n);
        rule += "---:|---:|";
    }
    o += "\n" + rule + "\n";
    for (const GapRow& r : rows) {
        o += fmt::format("| {} | {} | {} | {} |", r.scene, r.grid, fx(r.paper_os / r.os_priced), fx(r.paper_ic / r.ic_priced));
        for (const std::string& n : names) {
            const HypothesisResult* h = find(r, n);
            o += h ? fmt::format(" {} | {} |", fx(r.paper_os / h->os), fx(r.paper_ic / h->ic)) : std::string(" - | - |");
        }
        o += "\n";
    }
    return o;
}

// Per scene over its grids: the paper's OS against our voxel steps, its IC against our tests.
std::string fits_table(std::span<const GapRow> rows) {
    std::map<std::string, std::vector<const GapRow*>> by_scene;
    std::vector<std::string> order;
    for (const GapRow& r : rows) {
        if (!by_scene.count(r.scene)) order.push_back(r.scene);
        by_scene[r.scene].push_back(&r);
    }
    std::string o = "| scene | paper OS per our voxel step | paper OS fixed, per ray | paper IC per our test | "
                    "paper IC fixed (M) |\n|---|---:|---:|---:|---:|\n";
    for (const std::string& s : order) {
        const auto& rs = by_scene[s];
        if (rs.size() < 2) continue;
        std::vector<double> steps, os, tests, ic;
        for (const GapRow* r : rs) {
            steps.push_back(r->ours.counts.steps);
            os.push_back(r->paper_os);
            tests.push_back(r->ours.counts.triangle_tests + r->ours.counts.quadric_tests);
            ic.push_back(r->paper_ic);
        }
        auto fit = [](const std::vector<double>& x, const std::vector<double>& y) -> std::optional<LineFit> {
            try {
                return fit_line(x, y);
            } catch (const PaperError&) { // the same count at every grid: no line
                return std::nullopt;
            }
        };
        const std::optional<LineFit> fo = fit(steps, os), fi = fit(tests, ic);
        o += fmt::format("| {} | {} | {} | {} | {} |\n", s, fo ? fmt::format("{:.1f}", fo->slope) : "-",
                         fo ? fmt::format("{:.0f}", fo->intercept / rs[0]->ours.counts.rays) : "-",
                         fi ? fmt::format("{:.1f}", fi->slope) : "-", fi ? fmt::format("{:.0f}", fi->intercept / 1e6) : "-");
    }
    return o;
}

} // namespace

std::string gaps_markdown(std::span<const GapRow> rows) {
    std::string o;
    o += "### Counts: ours (native renderer) against what the paper's cycles imply (millions)\n\n";
    const Prices p = paper_prices();
    o += fmt::format("Paper steps = (OS - {:g} x 512^2) / {:g}; paper VISITs = IC communication / {:g}; paper tests = IC / "
                     "the mean price of a test in our mix ({:g} per triangle, {:g} per quadric).\n\n",
                     p.init, p.step, kernels::kPaper.fifo_ray, p.triangle, p.quadric);
    o += counts_table(rows);
    o += "\n### Attribution per stage (millions of cycles; factors multiply: paper/ours = kernel x its factor x "
         "unexplained)\n\n";
    o += "kernel = our counts at the paper's step costs / our cycles; workload at SPD view = paper / our counts at "
         "the paper's step costs; its factor = the adopted hypothesis' cycles / our counts' at the paper's costs.\n\n";
    o += attribution_table(rows);
    o += "\n### Every hypothesis: the paper's cycles over the cycles it predicts (1 = explained)\n\n";
    o += hypotheses_table(rows);
    o += "\n### Line fits over the grids: the paper's cycles against our counts\n\n";
    o += fits_table(rows);
    return o;
}

std::string gaps_json(std::span<const GapRow> rows) {
    auto counts = [](const WorkCounts& w) {
        return nlohmann::json{{"eye_rays", w.eye_rays},           {"rays", w.rays},
                              {"voxel_steps", w.steps},           {"visits", w.visits},
                              {"triangle_tests", w.triangle_tests}, {"quadric_tests", w.quadric_tests},
                              {"quadric_two_roots", w.quadric_two_roots}};
    };
    nlohmann::json a = nlohmann::json::array();
    for (const GapRow& r : rows) {
        nlohmann::json j{{"scene", r.scene},
                         {"grid", r.grid},
                         {"paper", {{"os", r.paper_os}, {"ic", r.paper_ic}, {"os_comm", r.paper_os_comm}, {"ic_comm", r.paper_ic_comm}}},
                         {"ours", {{"os", r.ours.os}, {"ic", r.ours.ic}, {"counts", counts(r.ours.counts)}}},
                         {"implied", {{"voxel_steps", r.implied_steps}, {"visits", r.implied_visits}, {"tests", r.implied_tests}}}};
        for (const Stage& s : stages(r))
            j["stages"][s.name] = {{"paper", s.paper},
                                   {"ours", s.ours},
                                   {"priced", s.priced},
                                   {"kernel", s.kernel},
                                   {"adopted", s.adopted ? nlohmann::json(*s.adopted) : nlohmann::json(nullptr)},
                                   {"explained", s.explained},
                                   {"unexplained", s.paper / s.explained}};
        for (const HypothesisResult& h : r.hypotheses)
            j["hypotheses"].push_back({{"name", h.name}, {"os", h.os}, {"ic", h.ic}, {"counts", counts(h.counts)}});
        a.push_back(j);
    }
    return nlohmann::json{{"gaps", a}}.dump(2) + "\n";
}

std::string gaps_csv(std::span<const GapRow> rows) {
    std::string o = "scene,grid,stage,paper,ours,kernel,priced,adopted,explained,unexplained\n";
    for (const GapRow& r : rows)
        for (const Stage& s : stages(r))
            o += fmt::format("{},{},{},{:.0f},{:.0f},{:.4f},{:.0f},{},{:.0f},{:.4f}\n", r.scene, r.grid, s.name, s.paper,
                             s.ours, s.kernel, s.priced, s.adopted ? *s.adopted : "", s.explained, s.paper / s.explained);
    return o;
}

} // namespace nesshi::paper
