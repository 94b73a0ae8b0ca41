// LoopReport::svg: the loop report as a picture, as the modulo-scheduling literature draws it: the
// reservation table (one row per cycle of the II, one column per issue slot, then the register
// ports used of those the machine has) and, below, each register's lifetime on a cycle axis marked
// at every multiple of the II. Ops are told apart by name in their cell, and by colour by class.
#include "sched/loop_report.hpp"

#include "base/xml.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <string>

namespace nesshi::sched {
namespace {

using base::xml_escape;

// Okabe and Ito's palette (readable with the common colour-vision deficiencies), by op class.
const std::map<std::string, std::string> kClassColour = {
    {"alu", "#E69F00"}, {"mul", "#D55E00"}, {"fadd", "#56B4E9"}, {"fmul", "#0072B2"}, {"fdiv", "#CC79A7"},
    {"load", "#009E73"}, {"store", "#F0E442"}, {"branch", "#999999"}, {"fifo", "#BBBBBB"}, {"misc", "#DDDDDD"}};

std::string colour(const std::string& cls) {
    const auto it = kClassColour.find(cls);
    return it == kClassColour.end() ? "#FFFFFF" : it->second;
}

constexpr int kMargin = 20, kCycleCol = 56, kSlotCol = 84, kPortCol = 84, kRow = 26, kLifeRow = 18, kLabelCol = 70;

void label_at(std::string& o, int x, int y, const std::string& s, const char* anchor = "middle", int size = 12,
          const char* weight = "normal", const char* fill = "black") {
    o += fmt::format(R"(<text x="{}" y="{}" text-anchor="{}" font-size="{}" font-weight="{}" fill="{}">{}</text>)" "\n", x, y,
                     anchor, size, weight, fill, xml_escape(s));
}

// Black text, or white on the two darkest fills.
const char* ink(const std::string& cls) { return cls == "fmul" || cls == "mul" ? "white" : "black"; }

// A pipelined loop's ops by iteration stage: the same palette in order, grey for loop control.
const char* kStageColour[] = {"#56B4E9", "#E69F00", "#009E73", "#F0E442", "#CC79A7", "#0072B2", "#D55E00", "#999999"};
std::string stage_colour(int stage) {
    if (stage < 0) return "#DDDDDD";
    return kStageColour[static_cast<std::size_t>(stage) % std::size(kStageColour)];
}
const char* stage_ink(int stage) { return stage >= 0 && (stage % 8 == 5 || stage % 8 == 6) ? "white" : "black"; }

} // namespace

std::string LoopReport::svg() const {
    const char* files[2] = {"IRF", "FPRF"};
    const int ncols = static_cast<int>(slots.size());
    const int table_w = kCycleCol + ncols * kSlotCol + 4 * kPortCol;
    const int rows = static_cast<int>(table.size());
    int end = std::max(ii, 1);
    for (const Lifetime& l : lifetimes) end = std::max(end, l.born + std::max(l.cycles, 1));
    const double px = std::clamp(560.0 / end, 6.0, 40.0); // pixels per cycle on the lifetime axis
    const int life_w = kLabelCol + static_cast<int>(px * end) + 20;
    const int width = 2 * kMargin + std::max({table_w, life_w, 520});
    const int table_top = kMargin + 56;
    const int life_top = table_top + (rows + 1) * kRow + 46;
    const int legend_top = life_top + 30 + static_cast<int>(lifetimes.size()) * kLifeRow + 16;
    const int height = legend_top + 30;
    int stages = 0; // colour by stage when the table has them
    for (const TableRow& row : table)
        for (const TableRow::Op& op : row.ops) stages = std::max(stages, op.stage + 1);
    auto fill = [&](const TableRow::Op& op) { return stages ? stage_colour(op.stage) : colour(op.op_class); };
    auto text_ink = [&](const TableRow::Op& op) { return stages ? stage_ink(op.stage) : ink(op.op_class); };

    std::string o = fmt::format(R"(<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}" )"
                                R"(font-family="DejaVu Sans, Helvetica, Arial, sans-serif">)" "\n",
                                width, height, width, height);
    o += fmt::format(R"(<rect width="{}" height="{}" fill="white"/>)" "\n", width, height);
    label_at(o, kMargin, kMargin + 14, fmt::format("{}: {} at {}, on {}", label, dispatch ? "dispatch body" : "loop", source, machine),
         "start", 15, "bold");
    label_at(o, kMargin, kMargin + 34, fmt::format("II {}  ResMII {}  RecMII {}  {} ops  -  {}", ii, res_mii, rec_mii, ops, verdict),
         "start", 12);

    // The reservation table: header, then one row per body cycle.
    int x = kMargin;
    const int y0 = table_top;
    label_at(o, x + kCycleCol / 2, y0 + 17, "cycle", "middle", 12, "bold");
    for (int c = 0; c < ncols; ++c) label_at(o, x + kCycleCol + c * kSlotCol + kSlotCol / 2, y0 + 17, slots[c], "middle", 12, "bold");
    const int ports_x = x + kCycleCol + ncols * kSlotCol;
    for (int f = 0; f < 2; ++f) {
        label_at(o, ports_x + (2 * f) * kPortCol + kPortCol / 2, y0 + 17, fmt::format("{} rd /{}", files[f], read_ports[f]), "middle", 11, "bold");
        label_at(o, ports_x + (2 * f + 1) * kPortCol + kPortCol / 2, y0 + 17, fmt::format("{} wr /{}", files[f], write_ports[f]), "middle",
             11, "bold");
    }
    for (int r = 0; r < rows; ++r) {
        const int y = y0 + (r + 1) * kRow;
        label_at(o, x + kCycleCol / 2, y + 17, std::to_string(r));
        for (int c = 0; c < ncols; ++c)
            o += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#CCCCCC"/>)" "\n",
                             x + kCycleCol + c * kSlotCol, y, kSlotCol, kRow);
        for (const TableRow::Op& op : table[static_cast<std::size_t>(r)].ops) {
            const auto it = std::find(slots.begin(), slots.end(), op.slot);
            const int c = static_cast<int>(it - slots.begin());
            const int cx = x + kCycleCol + c * kSlotCol;
            const std::string what = op.stage >= 0 ? fmt::format("{}, stage {}", op.op_class, op.stage) : op.op_class;
            o += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}" stroke="#333333"><title>{} on {} ({})</title></rect>)" "\n",
                             cx + 2, y + 2, kSlotCol - 4, kRow - 4, fill(op), xml_escape(op.op), xml_escape(op.slot),
                             xml_escape(what));
            label_at(o, cx + kSlotCol / 2, y + 17, op.op, "middle", 12, "normal", text_ink(op));
        }
        for (int k = 0; k < 4; ++k) {
            const int f = k / 2;
            const bool wr = k % 2;
            const int used = wr ? table[static_cast<std::size_t>(r)].writes[f] : table[static_cast<std::size_t>(r)].reads[f];
            const std::uint32_t cap = wr ? write_ports[f] : read_ports[f];
            const int px0 = ports_x + k * kPortCol;
            const int bar = cap ? static_cast<int>((kPortCol - 8) * std::min<double>(1.0, double(used) / cap)) : 0;
            o += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#CCCCCC"/>)" "\n", px0, y, kPortCol, kRow);
            if (bar > 0)
                o += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}"/>)" "\n", px0 + 4, y + 5, bar, kRow - 10,
                                 used >= static_cast<int>(cap) ? "#D55E00" : "#9ECAE1");
            label_at(o, px0 + kPortCol / 2, y + 17, fmt::format("{}", used));
        }
    }

    // Lifetimes: a bar per register from its write's issue, over cycles; dashed lines every II.
    label_at(o, kMargin, life_top - 14, fmt::format("register lifetimes (MaxLive: IRF {}, FPRF {}); dashed lines every II = {} cycles",
                                               max_live[0], max_live[1], ii), "start", 12, "bold");
    const int ax = kMargin + kLabelCol;
    const int axis_bottom = life_top + static_cast<int>(lifetimes.size()) * kLifeRow + 4;
    for (int c = 0; c <= end; c += std::max(ii, 1)) {
        const int lx = ax + static_cast<int>(c * px);
        o += fmt::format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888888" stroke-dasharray="4 3"/>)" "\n", lx, life_top - 4,
                         lx, axis_bottom);
        label_at(o, lx, axis_bottom + 14, std::to_string(c), "middle", 10);
    }
    for (std::size_t k = 0; k < lifetimes.size(); ++k) {
        const Lifetime& l = lifetimes[k];
        const int y = life_top + static_cast<int>(k) * kLifeRow;
        label_at(o, ax - 6, y + 13, fmt::format("{} ({})", l.reg, l.cycles), "end", 11);
        o += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}" stroke="#333333"/>)" "\n", ax + static_cast<int>(l.born * px),
                         y + 3, std::max(2, static_cast<int>(std::max(l.cycles, 1) * px)), kLifeRow - 6,
                         l.file == 1 ? "#56B4E9" : "#E69F00");
    }

    if (stages) { // Legend: the stages, and loop control.
        int lx = kMargin;
        label_at(o, lx, legend_top + 13, "iteration stage:", "start", 11, "bold");
        lx += 100;
        bool control = false;
        for (const TableRow& row : table)
            for (const TableRow::Op& op : row.ops) control = control || op.stage < 0;
        for (int st = control ? -1 : 0; st < stages; ++st) {
            o += fmt::format(R"(<rect x="{}" y="{}" width="14" height="14" fill="{}" stroke="#333333"/>)" "\n", lx, legend_top + 2,
                             stage_colour(st));
            const std::string name = st < 0 ? "loop control" : std::to_string(st);
            label_at(o, lx + 18, legend_top + 13, name, "start", 11);
            lx += 26 + 7 * static_cast<int>(name.size()) + 8;
        }
        o += "</svg>\n";
        return o;
    }
    // Legend: the op classes the table uses.
    std::vector<std::string> used;
    for (const TableRow& row : table)
        for (const TableRow::Op& op : row.ops)
            if (std::find(used.begin(), used.end(), op.op_class) == used.end()) used.push_back(op.op_class);
    std::sort(used.begin(), used.end());
    int lx = kMargin;
    label_at(o, lx, legend_top + 13, "op classes:", "start", 11, "bold");
    lx += 76;
    for (const std::string& cls : used) {
        o += fmt::format(R"(<rect x="{}" y="{}" width="14" height="14" fill="{}" stroke="#333333"/>)" "\n", lx, legend_top + 2, colour(cls));
        label_at(o, lx + 18, legend_top + 13, cls, "start", 11);
        lx += 26 + 7 * static_cast<int>(cls.size()) + 8;
    }
    o += "</svg>\n";
    return o;
}

} // namespace nesshi::sched
