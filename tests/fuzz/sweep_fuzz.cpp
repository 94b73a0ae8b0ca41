// Fuzz target `sweep`: the input is a sweep spec (TOML), optionally followed by a line `%%` and
// the text of a stored cell. The spec goes through parse_sweep_spec; an accepted one of at most
// 64 cells through sweep_cell_count, sweep_product, sweep_cells and sweep_inputs of every cell,
// and the outputs (CSV, JSON lines, chart) from the cells' stored texts. The cell text goes
// through the loading a resumed sweep or paper does (stale_reasons against the provenance of a
// fixed cell, parse_cell): as written, with its digest recomputed (so a tampered provenance
// reaches the comparison), and stamped afresh (stamp_cell). Nothing is ever simulated: the
// provenance and the cell of a run with zero counts are made once.
// Broken: a crash or an exception other than PaperError / base::Error; two cells of one spec with
// one id (one file); a cell of an accepted spec whose run inputs are refused; a freshly stamped
// cell that is not current, or one whose loaded text the outputs cannot read.
#include "check.hpp"

#include "machine/machine.hpp"
#include "machine/provenance.hpp"
#include "paper/paper.hpp"
#include "paper/sweep.hpp"
#include "rt/render.hpp"
#include "rt/scene.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>
#include <vector>

using namespace nesshi;

namespace {

constexpr std::size_t kMaxInput = 4096;
constexpr std::size_t kMaxCells = 64; // cells listed and output per spec

constexpr const char* kFixedSpec = "[axes]\nscene = \"balls:1\"\nsize = 2\ngrid = 2\n";

struct Fixed {
    paper::CellKey key{"balls:1", 2, machine::Model::V, 2};
    machine::Provenance provenance, other; // the fixed cell's, and one with a different grid
    std::string cell;                      // its stored text: a run with zero counts, stamped
};

const Fixed& fixed() {
    static const Fixed f = [] {
        Fixed x;
        const paper::SweepSpec s = paper::parse_sweep_spec(kFixedSpec, "fixed.toml");
        const paper::SweepRunInputs in = paper::sweep_inputs(s, paper::sweep_cells(s).at(0));
        x.provenance = machine::provenance(in.scene, in.grid, in.render, in.machine);
        x.other = x.provenance;
        x.other["grid"] = "3";
        const rt::PreparedScene prep = rt::prepare(rt::load_scene(in.scene), in.grid);
        machine::Result r; // never rendered: zero counts
        x.cell = paper::stamp_cell(rt::stats_text(machine::stats_json(prep, in.render, in.machine, r)), x.provenance);
        return x;
    }();
    return f;
}

// A stored text that loads (current) must be one the outputs and parse_cell read.
void loaded(const std::string& text, std::vector<std::string>& texts) {
    try {
        (void)paper::parse_cell(fixed().key, text, "fuzz.json");
    } catch (const paper::PaperError&) {
    }
    texts.push_back(text);
}

// The loading of a stored cell, three ways.
void load_cell(const std::string& text, std::vector<std::string>& current) {
    const Fixed& f = fixed();
    try { // as written
        if (paper::stale_reasons(text, f.provenance, "fuzz.json").empty()) loaded(text, current);
    } catch (const paper::PaperError&) {
    }
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return;
    nlohmann::json redigested = j; // its provenance as tampered, its digest as the tool writes it
    redigested["digest"] = machine::result_digest(j);
    const std::string again = redigested.dump(2) + "\n";
    try {
        if (paper::stale_reasons(again, f.provenance, "fuzz.json").empty()) loaded(again, current);
        (void)paper::stale_reasons(again, f.other, "fuzz.json");
    } catch (const paper::PaperError&) {
    }
    const std::string stamped = paper::stamp_cell(text, f.provenance);
    std::vector<std::string> why;
    try {
        why = paper::stale_reasons(stamped, f.provenance, "fuzz.json");
    } catch (const paper::PaperError& e) {
        fuzz::fail("a freshly stamped cell loads", stamped + e.what());
    }
    fuzz::check(why.empty(), "a freshly stamped cell is current", stamped + (why.empty() ? "" : why.front()));
    fuzz::check(!paper::stale_reasons(stamped, f.other, "fuzz.json").empty(), "a cell of another run is stale", stamped);
    loaded(stamped, current);
}

void sweep_spec(const std::string& text, const std::vector<std::string>& current) {
    paper::SweepSpec s;
    try {
        s = paper::parse_sweep_spec(text, "fuzz.toml");
    } catch (const base::Error&) { // PaperError, a located message
        return;
    }
    const std::size_t n = paper::sweep_cell_count(s);
    (void)paper::sweep_product(s);
    if (n > kMaxCells) return;
    const std::vector<paper::SweepCell> cells = paper::sweep_cells(s);
    fuzz::check(cells.size() == n, "sweep_cells lists sweep_cell_count cells");
    std::set<std::string> ids;
    for (const paper::SweepCell& c : cells) {
        std::string axes;
        for (std::size_t i = 0; i < c.values.size(); ++i) axes += s.axes[i].name + "=" + c.values[i] + "\n";
        fuzz::check(ids.insert(c.id).second, "each cell of a spec has a file of its own", text + "----\n" + axes + c.id);
        try {
            (void)paper::sweep_inputs(s, c);
        } catch (const paper::PaperError& e) {
            fuzz::fail("every cell of an accepted spec has its run inputs", text + "----\n" + axes + e.what());
        }
    }
    // The cells' stored texts: the fixed cell, the input's cells that loaded, and no result.
    std::vector<std::string> texts;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const std::size_t k = i % (current.size() + 2);
        texts.push_back(k == 0 ? fixed().cell : k == 1 ? std::string() : current[k - 2]);
    }
    try {
        (void)paper::sweep_csv(s, cells, texts);
        (void)paper::sweep_jsonl(s, cells, texts);
        (void)paper::sweep_chart_svg(s, cells, texts);
    } catch (const base::Error&) {
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxInput) return 0;
    if (std::getenv("NESSHI_FUZZ_PRINT_CELL")) std::fputs(fixed().cell.c_str(), stdout); // a seed for corpus/sweep
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const std::size_t sep = all.find("\n%%\n");
    const std::string spec(all.substr(0, sep));
    std::vector<std::string> current;
    if (sep != std::string_view::npos) load_cell(std::string(all.substr(sep + 4)), current);
    sweep_spec(spec, current);
    return 0;
}
