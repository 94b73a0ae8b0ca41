#include "kernel_build_json.hpp"

namespace nesshi::machine {

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

} // namespace nesshi::machine
