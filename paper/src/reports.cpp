// Writes every report of a paper run into the output folder.
#include "paper/paper.hpp"
#include "base/write_file.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace nesshi::paper {

std::vector<std::string> write_reports(const PaperData& d, const std::string& out_dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec) throw PaperError(base::SourceLoc(out_dir), fmt::format("cannot create: {}", ec.message()));
    std::vector<std::string> names;
    auto write = [&](const std::string& name, const std::string& text) {
        base::replace_file((fs::path(out_dir) / name).string(), text);
        names.push_back(name);
    };
    const std::pair<const char*, Table> tables[] = {
        {"table2", table2(d)}, {"table3", table3(d)}, {"table4", table4(d)}};
    for (const auto& [name, table] : tables) {
        write(fmt::format("{}.md", name), to_markdown(table));
        write(fmt::format("{}.csv", name), to_csv(table));
    }
    write("fig6.svg", fig6_svg(d));
    // The gaps page (written by hand from `nesshi paper gaps`) outlives a re-run: keep its link.
    std::string summary = summary_markdown(d);
    if (fs::exists(fs::path(out_dir) / "gaps.md"))
        summary += "\nWhy our absolute cycles differ from the paper's, cell by cell (kernel speed, workload, tested "
                   "hypotheses, what stays unexplained): [gaps.md](gaps.md).\n";
    write("summary.md", summary);
    return names;
}

} // namespace nesshi::paper
