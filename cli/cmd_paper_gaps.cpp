// `nesshi paper gaps`: attribute the gaps of our Table 2 against the paper's to kernel speed,
// workload and the hypotheses of paper/gaps.hpp (native renders + the model V cells of `nesshi paper`).
#include "status.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "lists.hpp"
#include "outputs.hpp"
#include "ranges.hpp"

#include "base/write_file.hpp"
#include "paper/gaps.hpp"
#include "paper/paper.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <memory>

namespace nesshi::cli {

namespace {

struct GapsArgs {
    paper::GapsOptions o;
    std::string scenes = "balls,mount,rings,tetra,tree", grids = "20,50,100";
    std::string out, json;
    bool quiet = false;
};

void run(GapsArgs& a) {
    a.o.scenes = split_list(a.scenes);
    a.o.grids = parse_grids(a.grids);
    for (const std::string& s : a.o.scenes)
        for (int g : a.o.grids)
            if (!paper::find_published_comm(s, g))
                throw UsageError(fmt::format("the paper has no Table 2 row for {} at grid {}", s, g));
    refuse_stdout("--out", a.out, "it is a folder (tables, CSV, JSON and the chart)");
    const bool json_stdout = stdout_output({{"--json", a.json}});
    check_outputs({a.json});
    if (!a.out.empty()) {
        std::filesystem::create_directories(a.out);
        for (const char* f : {"gaps-tables.md", "gaps.csv", "gaps.json", "gaps.svg"})
            check_output((std::filesystem::path(a.out) / f).string());
    }
    if (!a.quiet) a.o.progress = [](const std::string& line) { status("{}\n", line); };
    std::vector<paper::GapRow> rows;
    try {
        rows = paper::run_gaps(a.o);
    } catch (const paper::PaperError& e) {
        throw base::Error(e.message());
    }
    const std::string md = paper::gaps_markdown(rows), js = paper::gaps_json(rows);
    if (!a.json.empty()) base::write_file(a.json, js);
    if (!a.out.empty()) {
        const std::filesystem::path d(a.out);
        base::write_file((d / "gaps-tables.md").string(),
                         fmt::format("# Table 2 gaps: generated tables\n\nWritten by `nesshi paper gaps --cells {} --out {}`; "
                                     "read with gaps.md.\n\n{}",
                                     a.o.cells_dir, a.out, md));
        base::write_file((d / "gaps.csv").string(), paper::gaps_csv(rows));
        base::write_file((d / "gaps.json").string(), js);
        base::write_file((d / "gaps.svg").string(), paper::gaps_svg(rows));
    }
    fmt::print(json_stdout ? stderr : stdout, "{}", md);
}

} // namespace

void add_paper_gaps(CLI::App& paper_cmd) {
    auto* cmd = paper_cmd.add_subcommand(
        "gaps", "Attribute our Table 2's gaps against the paper's to kernel speed, workload and hypotheses");
    auto a = std::make_shared<GapsArgs>();
    cmd->add_option("--cells", a->o.cells_dir, "folder of nesshi paper's cells (model V, at --size)")->required();
    cmd->add_option("--size", a->o.size, "image size of the cells and the native renders (default 512)")
        ->check(between(1, 16384));
    cmd->add_option("--scenes", a->scenes, "scenes, comma-separated (default balls,mount,rings,tetra,tree)");
    cmd->add_option("--grids", a->grids, "grids, comma-separated (default 20,50,100)");
    cmd->add_option("--threads", a->o.threads, "native renderer threads (default: all cores)")->check(between(0, 1024));
    cmd->add_option("--out", a->out, "also write gaps-tables.md, gaps.csv, gaps.json and gaps.svg to this folder");
    cmd->add_option("--json", a->json, "the rows as JSON to FILE ('-': stdout, the tables go to stderr)");
    cmd->add_flag("-q,--quiet", a->quiet, "no progress");
    cmd->callback([a] { run(*a); });
}

} // namespace nesshi::cli
