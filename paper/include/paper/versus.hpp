// Two runs of the paper side by side (`nesshi paper versus A B`), e.g. the ideal presets against
// the `-real` ones: per scene x grid, each run's M and V cycles and M/V, how much V slowed down,
// the V runs' OS and IC ILP, and the paper's M/V.
//
//   paper::PaperOptions o;  o.size = 256;
//   o.out_dir = "ideal";  paper::PaperData a = paper::load_paper_data(o);
//   o.out_dir = "real";   paper::PaperData b = paper::load_paper_data(o);
//   std::string md = paper::to_markdown(paper::versus_table({"ideal", a}, {"real", b}));
#pragma once

#include "paper/paper.hpp"

#include <string>

namespace nesshi::paper {

// The stored cells of o.out_dir for matrix_cells(o), nothing run; throws PaperError naming the
// first cell file that is missing or malformed.
PaperData load_paper_data(const PaperOptions& o);

struct VersusRun {
    std::string name; // the column prefix: "ideal", "real"
    const PaperData& data;
};
// Rows: the scenes and grids of `a` (both runs must have their M and V cells).
Table versus_table(const VersusRun& a, const VersusRun& b);

} // namespace nesshi::paper
