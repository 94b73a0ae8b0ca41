// A region's schedule as JSON (`nesshi pipeline --json`): the figures of the report's first lines
// and, with `.trip`, how the schedule was chosen (TripChoice::json).
#include "sched/pipeline.hpp"

#include <nlohmann/json.hpp>

namespace nesshi::sched {

std::string LoopSummary::json() const {
    nlohmann::ordered_json j = {{"line", line},       {"while", is_while},   {"ii", ii},
                                {"mii", mii},         {"proven_mii", proven_mii}, {"res_mii", res_mii},  {"rec_mii", rec_mii},
                                {"stages", stages},   {"unroll", unroll},    {"groups", groups},
                                {"iteration", iteration_cycles},
                                {"longest_path", iteration_lower},              {"trip", nullptr}};
    if (trip) j["trip"] = nlohmann::ordered_json::parse(trip->json());
    return j.dump();
}

} // namespace nesshi::sched
