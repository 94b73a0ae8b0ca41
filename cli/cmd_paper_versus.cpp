// `nesshi paper versus A B`: two stored paper runs' Table 3 side by side (paper/versus.hpp), as
// Markdown on stdout and optionally CSV.
#include "commands.hpp"
#include "errors.hpp"
#include "lists.hpp"
#include "outputs.hpp"
#include "ranges.hpp"

#include "base/write_file.hpp"
#include "paper/versus.hpp"

#include <fmt/format.h>

#include <memory>

namespace nesshi::cli {

namespace {

struct VersusArgs {
    std::string a, b, names, csv;
    int size = 512;
    std::string scenes = "balls,mount,rings,tetra,tree", grids = "20,50,100";
};

void run(const VersusArgs& v) {
    std::vector<std::string> names = {v.a, v.b};
    if (!v.names.empty()) {
        names = split_list(v.names);
        if (names.size() != 2) throw UsageError(fmt::format("--names takes two names, A,B (got '{}')", v.names));
    }
    check_outputs({v.csv});
    paper::PaperOptions o;
    o.size = v.size;
    o.scenes = split_list(v.scenes);
    o.grids = parse_grids(v.grids);
    o.models = {machine::Model::M, machine::Model::V};
    try {
        paper::validate(o);
    } catch (const paper::PaperError& e) {
        throw UsageError(e.message());
    }
    o.out_dir = v.a;
    const paper::PaperData a = paper::load_paper_data(o);
    o.out_dir = v.b;
    const paper::PaperData b = paper::load_paper_data(o);
    const paper::Table t = paper::versus_table({names[0], a}, {names[1], b});
    if (!v.csv.empty()) base::write_file(v.csv, paper::to_csv(t));
    fmt::print("{}", paper::to_markdown(t));
}

} // namespace

void add_paper_versus(CLI::App& paper_cmd) {
    auto* cmd = paper_cmd.add_subcommand("versus", "Two stored paper runs' Table 3 side by side (e.g. ideal against -real machines)");
    auto v = std::make_shared<VersusArgs>();
    cmd->add_option("A", v->a, "the first run's --out folder")->required();
    cmd->add_option("B", v->b, "the second run's --out folder")->required();
    cmd->add_option("--names", v->names, "the runs' column names, A,B (default: the folders)");
    cmd->add_option("--size", v->size, "image size of both runs (default 512)")->check(between(1, 16384));
    cmd->add_option("--scenes", v->scenes, "scenes, comma-separated (default balls,mount,rings,tetra,tree)");
    cmd->add_option("--grids", v->grids, "grids, comma-separated (default 20,50,100)");
    cmd->add_option("--csv", v->csv, "also write the table as CSV to FILE");
    cmd->callback([v] { run(*v); });
}

} // namespace nesshi::cli
