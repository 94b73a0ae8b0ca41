// A metric of a sweep: a dotted path to a number in a cell's stats JSON (internal to src/paper).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace nesshi::paper {

// The number at `path` ("cycles.os.processing"); nullopt when absent or not a number.
std::optional<nlohmann::json> sweep_metric(const nlohmann::json& doc, const std::string& path);

// The stats JSON of a run with every optional part present (counts zero): a metric no cell can
// have is one this document lacks.
const nlohmann::json& sweep_metric_schema();

} // namespace nesshi::paper
