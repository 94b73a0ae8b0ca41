// Cell formats and notes shared by the tables and the summary (internal to src/paper).
#pragma once

#include "base/xml.hpp"
#include "paper/paper.hpp"
#include "paper/published.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::paper {

using base::xml_escape;

inline const std::string kMissing = "—";

bool has_model(const PaperData& d, machine::Model m);    // asked for in this run
std::string format_published(const Published& p);      // 4581, ≈4900*, 1.73*
std::string format_range(const PublishedRange& r);     // 2.21–2.29
std::string format_ratio(const std::array<int, 3>& r); // 4:20:1
std::string format_quotient(double num, double den);   // 2.05, or — when den is 0
std::string format_scale(int size);                    // "×64"
double axis_step(double max);
// Tidy CSV fields (Table::csv_rows): cycles as integers, other numbers with every digit that
// round-trips, "" when missing, flags as 0/1; a published value as three columns (value,
// reconstructed: * in PAPER.md, approximate: ≈), and their header names.
std::string csv_field(std::uint64_t v, bool present);
std::string csv_field(double v, bool present = true);
std::string csv_flag(bool b);
void add_published_csv(std::vector<std::string>& row, const Published* p);
void add_published_csv_header(std::vector<std::string>& header, const std::string& name);
// The notes every table ends with: the scaling when size != 512, scenes not at the paper's size.
std::vector<std::string> common_notes(const PaperData& d);
inline constexpr const char* kReconstructedNote =
    "Paper columns: * marks cells PAPER.md reconstructed from the speed-up columns and the text (the printed tables "
    "are damaged there); ≈ an estimate.";

} // namespace nesshi::paper
