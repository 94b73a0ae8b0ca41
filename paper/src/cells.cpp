// Cell storage: file names, reading a cell's stats JSON back, atomic writes, lookup.
#include "paper/paper.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace nesshi::paper {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A file-name-safe label: an NFF path gives its stem, "tetra:1" gives "tetra_1".
std::string scene_label(const std::string& scene) {
    std::string s = scene;
    if (s.find('/') != std::string::npos || fs::path(s).extension() == ".nff") s = fs::path(s).stem().string();
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
    return s;
}

const json& member(const json& j, const char* key, const std::string& where) {
    if (!j.is_object() || !j.contains(key)) throw PaperError(fmt::format("missing \"{}\"", where + key));
    return j.at(key);
}

std::uint64_t count(const json& j, const char* key, const std::string& where) {
    const json& v = member(j, key, where);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
        throw PaperError(fmt::format("\"{}\" is not a cycle count", where + key));
    return v.get<std::uint64_t>();
}

double number_or_zero(const json& j, const char* key) {
    return j.is_object() && j.contains(key) && j.at(key).is_number() ? j.at(key).get<double>() : 0.0;
}

machine::StageCycles stage(const json& cycles, const char* name) {
    return machine::stage_cycles_from_json(member(cycles, name, "cycles."), fmt::format("cycles.{}.", name));
}

// A renamed or copied file must not pass for another cell.
void check_identity(const json& j, const CellKey& key) {
    const std::string want = machine::model_name(key.model);
    if (j.contains("model") && j["model"].is_string() && j["model"].get<std::string>() != want)
        throw PaperError(fmt::format("holds model {}, expected {}", j["model"].get<std::string>(), want));
    if (j.contains("size") && j["size"].is_array() && j["size"].size() == 2 && j["size"][0].is_number_integer() &&
        j["size"][0].get<int>() != key.size)
        throw PaperError(fmt::format("holds size {}, expected {}", j["size"][0].get<int>(), key.size));
}

} // namespace

std::string cell_file_name(const CellKey& k) {
    return fmt::format("{}-g{}-{}-{}.json", scene_label(k.scene), k.grid, machine::model_name(k.model), k.size);
}

CellRecord parse_cell(const CellKey& key, const std::string& text, const std::string& file) {
    try {
        const json j = json::parse(text);
        check_identity(j, key);
        const json& cycles = member(j, "cycles", "");
        CellRecord r;
        r.key = key;
        r.total = count(cycles, "total", "cycles.");
        if (key.model == machine::Model::M) r.s_cycles = count(cycles, "s_cycles", "cycles.");
        r.os = stage(cycles, "os");
        r.ic = stage(cycles, "ic");
        r.sc = stage(cycles, "sc");
        const json host = j.value("host", json::object());
        r.wall_seconds = number_or_zero(host, "wall_seconds");
        return r;
    } catch (const std::exception& e) { // json::exception or PaperError
        throw PaperError(base::SourceLoc(file), fmt::format("malformed cell file: {} (delete it to run the cell again)", e.what()));
    }
}

std::string stamp_cell(const std::string& json_text, const machine::Provenance& p) {
    json j = json::parse(json_text);
    j["provenance"] = p;
    j["digest"] = machine::result_digest(j);
    return j.dump(2) + "\n";
}

std::vector<std::string> stale_reasons(const std::string& json_text, const machine::Provenance& expected,
                                       const std::string& file, bool* other_build) {
    json j;
    try {
        j = json::parse(json_text);
    } catch (const json::exception& e) {
        throw PaperError(base::SourceLoc(file), fmt::format("malformed cell file: {} (delete it to run the cell again)", e.what()));
    }
    if (!j.is_object() || !j.contains("digest") || !j.contains("provenance")) return {"no provenance recorded"};
    if (!j["digest"].is_string() || j["digest"].get<std::string>() != machine::result_digest(j))
        throw PaperError(base::SourceLoc(file), "its results do not match its digest (edited by hand?); delete it to "
                                                "run the cell again");
    machine::Provenance stored;
    try {
        stored = j["provenance"].get<machine::Provenance>();
    } catch (const json::exception&) {
        throw PaperError(base::SourceLoc(file), "malformed cell file: \"provenance\" is not an object of strings "
                                                "(delete it to run the cell again)");
    }
    const auto why = machine::provenance_differences(stored, expected, other_build == nullptr);
    if (other_build) { // kept, and of another build, when nothing but the build differs
        const auto build = [](const machine::Provenance& p) { return p.contains("build") ? p.at("build") : std::string(); };
        *other_build = why.empty() && build(stored) != build(expected);
    }
    return why;
}

const CellRecord* PaperData::find(const std::string& scene, int grid, machine::Model m) const {
    // S lives in the M cell.
    const machine::Model stored = m == machine::Model::S ? machine::Model::M : m;
    auto it = std::find_if(cells.begin(), cells.end(), [&](const CellRecord& c) {
        return c.key.scene == scene && c.key.grid == grid && c.key.model == stored;
    });
    return it == cells.end() ? nullptr : &*it;
}

PaperData make_data(const PaperOptions& o, std::vector<CellRecord> cells) {
    PaperData d;
    d.size = o.size;
    d.scenes = o.scenes;
    d.grids = o.grids;
    std::sort(d.grids.begin(), d.grids.end());
    d.grids.erase(std::unique(d.grids.begin(), d.grids.end()), d.grids.end());
    for (machine::Model m : {machine::Model::S, machine::Model::M, machine::Model::V})
        if (wants(o, m)) d.models.push_back(m);
    d.cells = std::move(cells);
    return d;
}

} // namespace nesshi::paper
