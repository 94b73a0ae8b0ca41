// Tables 2, 3 and 4 of the paper, ours beside the published values (millions of cycles).
#include "report_format.hpp"

#include <fmt/format.h>

namespace nesshi::paper {

namespace {

double as_double(std::uint64_t v) { return static_cast<double>(v); }

// Ours in millions, then (size != 512) the same scaled to 512x512.
void add_cycles(std::vector<std::string>& row, const std::vector<std::uint64_t>& values, bool present) {
    for (std::uint64_t v : values) row.push_back(present ? format_mcycles(as_double(v)) : kMissing);
}
void add_scaled(const PaperData& d, std::vector<std::string>& row, const std::vector<std::uint64_t>& values,
                bool present) {
    if (d.size == 512) return;
    for (std::uint64_t v : values)
        row.push_back(present ? format_mcycles(as_double(v) * scale_to_paper(d.size)) : kMissing);
}
void add_scaled_header(const PaperData& d, std::vector<std::string>& header, std::initializer_list<const char*> names) {
    if (d.size == 512) return;
    for (const char* n : names) header.push_back(fmt::format("{} {}", n, format_scale(d.size)));
}

Table start(const PaperData& d, std::string title, std::vector<std::string> header) {
    Table t;
    t.title = std::move(title);
    t.header = std::move(header);
    t.notes = common_notes(d);
    return t;
}

} // namespace

Table table2(const PaperData& d) {
    Table t = start(d, "Table 2: model V, cycles of each stage (millions)",
                    {"scene", "grid", "OS proc", "IC proc", "SC proc", "OS comm", "IC comm", "SC comm", "OS wait",
                     "IC wait", "SC wait", "OS:IC:SC"});
    add_scaled_header(d, t.header, {"OS proc", "IC proc", "SC proc"});
    for (const char* h : {"paper OS proc", "paper IC proc", "paper SC proc", "paper OS:IC:SC"}) t.header.push_back(h);
    t.csv_header = {"scene", "grid", "size", "os_processing", "ic_processing", "sc_processing", "os_communication",
                    "ic_communication", "sc_communication", "os_wait", "ic_wait", "sc_wait",
                    "paper_os_processing_m512", "paper_ic_processing_m512", "paper_sc_processing_m512", "paper_ratio_os",
                    "paper_ratio_ic", "paper_ratio_sc", "paper_ratio_suspect"};
    bool suspect = false;
    for (const std::string& scene : d.scenes)
        for (int g : d.grids) {
            const CellRecord* v = d.find(scene, g, machine::Model::V);
            const CellRecord none;
            const CellRecord& c = v ? *v : none;
            std::vector<std::string> row = {scene, std::to_string(g)};
            add_cycles(row, {c.os.processing, c.ic.processing, c.sc.processing}, v);
            add_cycles(row, {c.os.communication, c.ic.communication, c.sc.communication}, v);
            add_cycles(row, {c.os.wait, c.ic.wait, c.sc.wait}, v);
            row.push_back(v ? format_ratio(load_ratio(c)) : kMissing);
            add_scaled(d, row, {c.os.processing, c.ic.processing, c.sc.processing}, v);
            const PublishedStages* ps = find_published_stages(paper_scene(scene), g);
            std::vector<std::string> tidy = {scene, std::to_string(g), std::to_string(d.size)};
            for (std::uint64_t x : {c.os.processing, c.ic.processing, c.sc.processing, c.os.communication,
                                    c.ic.communication, c.sc.communication, c.os.wait, c.ic.wait, c.sc.wait})
                tidy.push_back(csv_field(x, v));
            for (double x : {ps ? ps->os : 0, ps ? ps->ic : 0, ps ? ps->sc : 0}) tidy.push_back(csv_field(x, ps));
            for (int x : ps ? ps->ratio : std::array<int, 3>{}) tidy.push_back(ps ? std::to_string(x) : "");
            tidy.push_back(ps ? csv_flag(ps->ratio_suspect) : "");
            t.csv_rows.push_back(std::move(tidy));
            if (const PublishedStages* p = ps) {
                for (double x : {p->os, p->ic, p->sc}) row.push_back(fmt::format("{:.0f}", x));
                row.push_back(format_ratio(p->ratio) + (p->ratio_suspect ? " (?)" : ""));
                suspect = suspect || p->ratio_suspect;
            } else {
                row.insert(row.end(), 4, kMissing);
            }
            t.rows.push_back(std::move(row));
        }
    t.notes.insert(t.notes.begin(),
                   "proc = processing, comm = FIFO communication, wait = waiting on an empty input FIFO; OS:IC:SC is "
                   "the ratio of loads (processing + communication), the smallest = 1, rounded.");
    if (suspect)
        t.notes.push_back("(?): the printed ratio contradicts the printed processing columns (tree 20 gives ≈7:211:1, "
                          "tree 50 ≈14:85:1); probably misread in print.");
    return t;
}

Table table3(const PaperData& d) {
    Table t = start(d, "Table 3: ray-tracing time of models S, M, V (millions of cycles) and speed-ups",
                    {"scene", "grid", "S", "M", "V"});
    add_scaled_header(d, t.header, {"S", "M", "V"});
    for (const char* h : {"S/M", "M/V", "S/V", "paper S", "paper M", "paper V", "paper S/M", "paper M/V", "paper S/V"})
        t.header.push_back(h);
    t.csv_header = {"scene", "grid", "size", "s_cycles", "m_cycles", "v_cycles", "s_over_m", "m_over_v", "s_over_v"};
    for (const char* h : {"paper_s_m512", "paper_m_m512", "paper_v_m512", "paper_s_over_m", "paper_m_over_v", "paper_s_over_v"})
        add_published_csv_header(t.csv_header, h);
    for (const std::string& scene : d.scenes)
        for (int g : d.grids) {
            const CellRecord* m = d.find(scene, g, machine::Model::M);
            const CellRecord* v = d.find(scene, g, machine::Model::V);
            const double s_t = m ? as_double(s_time(*m)) : 0, m_t = m ? as_double(m->total) : 0;
            const double v_t = v ? as_double(v->total) : 0;
            std::vector<std::string> row = {scene, std::to_string(g)};
            const bool has_s = m && has_model(d, machine::Model::S), has_m = m && has_model(d, machine::Model::M);
            row.push_back(has_s ? format_mcycles(s_t) : kMissing);
            row.push_back(has_m ? format_mcycles(m_t) : kMissing);
            row.push_back(v ? format_mcycles(v_t) : kMissing);
            if (d.size != 512)
                for (auto [ok, x] : {std::pair{has_s, s_t}, std::pair{has_m, m_t}, std::pair{v != nullptr, v_t}})
                    row.push_back(ok ? format_mcycles(x * scale_to_paper(d.size)) : kMissing);
            row.push_back(has_s && has_m ? format_quotient(s_t, m_t) : kMissing);
            row.push_back(has_m ? format_quotient(m_t, v_t) : kMissing);
            row.push_back(has_s ? format_quotient(s_t, v_t) : kMissing);
            const PublishedTimes* pt = find_published_times(paper_scene(scene), g);
            std::vector<std::string> tidy = {scene, std::to_string(g), std::to_string(d.size)};
            tidy.push_back(csv_field(m ? s_time(*m) : 0, has_s));
            tidy.push_back(csv_field(m ? m->total : 0, has_m));
            tidy.push_back(csv_field(v ? v->total : 0, v != nullptr));
            tidy.push_back(csv_field(s_t / m_t, has_s && has_m && m_t > 0));
            tidy.push_back(csv_field(m_t / v_t, has_m && v && v_t > 0));
            tidy.push_back(csv_field(s_t / v_t, has_s && v && v_t > 0));
            for (const Published* x : {pt ? &pt->s : nullptr, pt ? &pt->m : nullptr, pt ? &pt->v : nullptr,
                                       pt ? &pt->s_over_m : nullptr, pt ? &pt->m_over_v : nullptr, pt ? &pt->s_over_v : nullptr})
                add_published_csv(tidy, x);
            t.csv_rows.push_back(std::move(tidy));
            if (const PublishedTimes* p = pt) {
                for (const Published& x : {p->s, p->m, p->v, p->s_over_m, p->m_over_v, p->s_over_v})
                    row.push_back(format_published(x));
            } else {
                row.insert(row.end(), 6, kMissing);
            }
            t.rows.push_back(std::move(row));
        }
    t.notes.insert(t.notes.begin(), "S is derived from the model-M run (the sum of the stages' loads on one processor, "
                                    "machine::Stats::s_cycles), not simulated separately.");
    t.notes.push_back(kReconstructedNote);
    return t;
}

// Table 4's metrics, once: the Markdown name, the CSV name, what it is of our cells (a stage's
// count in M over V, or a figure of V's), and the paper's range for it.
struct VliwMetric {
    const char* name;
    const char* csv;
    const machine::StageCycles CellRecord::*stage;
    std::uint64_t machine::StageCycles::*count; // M over V of this; nullptr: `value` of V
    double (machine::StageCycles::*value)() const;
    PublishedRange PublishedVliw::*paper;
};
const VliwMetric kVliwMetrics[] = {
    {"OS proc M/V", "os_processing_m_over_v", &CellRecord::os, &machine::StageCycles::processing, nullptr, &PublishedVliw::os_processing},
    {"OS comm M/V", "os_communication_m_over_v", &CellRecord::os, &machine::StageCycles::communication, nullptr, &PublishedVliw::os_communication},
    {"IC proc M/V", "ic_processing_m_over_v", &CellRecord::ic, &machine::StageCycles::processing, nullptr, &PublishedVliw::ic_processing},
    {"IC comm M/V", "ic_communication_m_over_v", &CellRecord::ic, &machine::StageCycles::communication, nullptr, &PublishedVliw::ic_communication},
    {"OS ILP", "os_ilp", &CellRecord::os, nullptr, &machine::StageCycles::ilp, &PublishedVliw::os_ilp},
    {"IC ILP", "ic_ilp", &CellRecord::ic, nullptr, &machine::StageCycles::ilp, &PublishedVliw::ic_ilp},
    {"OS util", "os_utilization", &CellRecord::os, nullptr, &machine::StageCycles::utilization, &PublishedVliw::os_utilization},
    {"IC util", "ic_utilization", &CellRecord::ic, nullptr, &machine::StageCycles::utilization, &PublishedVliw::ic_utilization},
};

Table table4(const PaperData& d) {
    Table t = start(d, "Table 4: VLIW against sequential stages (model V against M)", {"scene", "grid"});
    t.csv_header = {"scene", "grid", "size"};
    for (const VliwMetric& k : kVliwMetrics) {
        t.header.push_back(k.name);
        t.header.push_back(fmt::format("paper {}", k.name));
        t.csv_header.push_back(k.csv);
        t.csv_header.push_back(fmt::format("paper_{}_lo", k.csv));
        t.csv_header.push_back(fmt::format("paper_{}_hi", k.csv));
    }
    for (const std::string& scene : d.scenes)
        for (int g : d.grids) {
            const CellRecord* m = d.find(scene, g, machine::Model::M);
            const CellRecord* v = d.find(scene, g, machine::Model::V);
            const PublishedVliw* p = find_published_vliw(paper_scene(scene));
            std::vector<std::string> row = {scene, std::to_string(g)};
            std::vector<std::string> tidy = {scene, std::to_string(g), std::to_string(d.size)};
            for (const VliwMetric& k : kVliwMetrics) {
                if (k.count) {
                    const double num = m ? as_double((m->*k.stage).*k.count) : 0, den = v ? as_double((v->*k.stage).*k.count) : 0;
                    row.push_back(m && v ? format_quotient(num, den) : kMissing);
                    tidy.push_back(csv_field(num / den, m && v && den > 0));
                } else {
                    const double x = v ? ((v->*k.stage).*k.value)() : 0;
                    row.push_back(v ? fmt::format("{:.2f}", x) : kMissing);
                    tidy.push_back(csv_field(x, v != nullptr));
                }
                row.push_back(p ? format_range(p->*k.paper) : kMissing);
                tidy.push_back(p ? csv_field((p->*k.paper).lo) : "");
                tidy.push_back(p ? csv_field((p->*k.paper).hi) : "");
            }
            t.rows.push_back(std::move(row));
            t.csv_rows.push_back(std::move(tidy));
        }
    t.notes.insert(t.notes.begin(),
                   "proc/comm M/V: the stage's processing (communication) cycles in model M over model V. ILP: "
                   "operations per bundle over processing cycles; util: ILP over the units (4 in OS and IC), of model "
                   "V. The paper gives ranges over grids 20, 50 and 100 per scene.");
    return t;
}

} // namespace nesshi::paper
