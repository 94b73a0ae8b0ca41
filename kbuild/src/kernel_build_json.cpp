#include "kbuild/kernel_build_json.hpp"

namespace nesshi::kbuild {

nlohmann::json loop_json(const KernelLoop& l) {
    return {{"line", l.line},     {"kind", l.is_while ? "while" : "counted"},
            {"ii", l.ii},         {"mii", l.mii},
            {"stages", l.stages}, {"unroll", l.unroll}, {"rec_mii", l.rec_mii},
            {"iteration", l.iteration}, {"longest_path", l.longest_path}};
}

KernelLoop loop_from_json(const nlohmann::json& j) {
    return {j.at("line"),   j.at("kind") == "while", j.at("ii"),        j.at("mii"),
            j.at("stages"), j.at("unroll"),          j.at("rec_mii"),   j.at("iteration"), j.at("longest_path")};
}

nlohmann::json build_json(const KernelBuild& b) {
    nlohmann::json loops = nlohmann::json::array();
    for (const KernelLoop& l : b.loops) loops.push_back(loop_json(l));
    return {{"source", b.source}, {"machine", b.machine}, {"scheduled", b.scheduled},   {"blocks", b.blocks},
            {"blocks_shortest", b.blocks_shortest}, {"nops", b.nops},     {"choice", b.choice},   {"candidates", b.candidates}, {"loops", loops},
            {"loop_report", b.loop_report}};
}

KernelBuild build_from_json(const nlohmann::json& j) {
    KernelBuild b;
    b.source = j.at("source");
    b.machine = j.at("machine");
    b.scheduled = j.at("scheduled");
    b.blocks = j.at("blocks");
    b.blocks_shortest = j.at("blocks_shortest");
    b.nops = j.at("nops");
    b.choice = j.at("choice");
    b.candidates = j.at("candidates");
    for (const nlohmann::json& l : j.at("loops")) b.loops.push_back(loop_from_json(l));
    b.loop_report = j.at("loop_report");
    return b;
}

} // namespace nesshi::kbuild
