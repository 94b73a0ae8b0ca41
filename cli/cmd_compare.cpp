// `nesshi compare A.json B.json [...]`: machine runs side by side (paper/compare.hpp), as a
// Markdown table on stdout and optionally CSV.
#include "commands.hpp"
#include "errors.hpp"
#include "status.hpp"

#include "base/read_file.hpp"
#include "base/write_file.hpp"
#include "paper/compare.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>

namespace nesshi::cli {

void add_compare(CLI::App& app) {
    auto* cmd = app.add_subcommand("compare", "Machine runs side by side: stats JSON files or paper/sweep cells");
    auto files = std::make_shared<std::vector<std::string>>();
    auto csv = std::make_shared<std::string>();
    cmd->add_option("runs", *files, "two or more stats JSON files (render --stats-json) or stored cells")
        ->required()
        ->expected(2, -1);
    cmd->add_option("--csv", *csv, "also write the table as CSV to FILE ('-': stdout instead of the table)");
    cmd->callback([files, csv] {
        // Columns are named by the files' stems when those differ, else by the paths.
        std::vector<std::string> names;
        for (const std::string& f : *files) names.push_back(std::filesystem::path(f).stem().string());
        std::vector<std::string> sorted = names;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) names = *files;
        std::vector<std::pair<std::string, std::string>> runs;
        for (std::size_t i = 0; i < files->size(); ++i) runs.emplace_back(names[i], base::read_file((*files)[i]));
        const paper::Comparison c = paper::compare_runs(runs);
        for (const std::string& w : c.warnings) status("nesshi compare: warning: {}\n", w);
        if (*csv != "-") fmt::print("{}", paper::to_markdown(c.table));
        if (!csv->empty()) base::write_file(*csv, paper::to_csv(c.table));
    });
}

} // namespace nesshi::cli
