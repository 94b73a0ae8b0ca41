// `nesshi compare A.json B.json [...]`: machine runs side by side. Each input is a stats JSON
// (`render --stats-json`) or a stored paper or sweep cell (the same JSON with its provenance).
// Rows: what each run is (scene, model, size, grid, stage machines, options: "same" or "differs"
// from the first), total cycles, each stage's processing / communication / wait, ILP and utilization, the
// cache and FIFO figures, and the cycles of each kernel region (label) of the OS and IC stages;
// columns: each run, then each run against the first (its value / the first's).
//
//   paper::Comparison c = paper::compare_runs({{"ideal", text_a}, {"real", text_b}});
//   std::string md = paper::to_markdown(c.table), csv = paper::to_csv(c.table);
#pragma once

#include "paper/paper.hpp"

#include <string>
#include <utility>
#include <vector>

namespace nesshi::paper {

struct Comparison {
    Table table;
    // "the runs are of different scenes (tetra:1, balls:1): their cycles do not compare" (also
    // in the table's notes)
    std::vector<std::string> warnings;
};

// (name, JSON text) per run, at least two. Throws PaperError naming the run whose text is not a
// machine run's stats JSON.
Comparison compare_runs(const std::vector<std::pair<std::string, std::string>>& runs);

} // namespace nesshi::paper
