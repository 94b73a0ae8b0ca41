// A metric of a sweep: a dotted path to a number in a cell's stats JSON (internal to src/paper).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace nesshi::paper {

// The number at `path` ("cycles.os.processing"); nullopt when absent or not a number.
std::optional<nlohmann::json> sweep_metric(const nlohmann::json& doc, const std::string& path);

// The stats JSON of a run with every optional part present (counts zero): a metric no cell can
// have is one this document lacks.
const nlohmann::json& sweep_metric_schema();

// An axis value as a whole number, when it is one ("48"; not "4k", not "balls:1").
std::optional<long long> integer(const std::string& v);
// The cells' stats texts parsed; an empty text (no result) is null.
std::vector<nlohmann::json> parsed(const std::vector<std::string>& texts);

} // namespace nesshi::paper
