// Model names and the per-stage cycle sums.
#include "machine/machine.hpp"

namespace nesshi::machine {

const char* model_name(Model m) {
    switch (m) {
    case Model::S: return "S";
    case Model::M: return "M";
    case Model::V: return "V";
    }
    return "?";
}

bool parse_model(const std::string& s, Model& out) {
    if (s == "S" || s == "s") out = Model::S;
    else if (s == "M" || s == "m") out = Model::M;
    else if (s == "V" || s == "v") out = Model::V;
    else return false;
    return true;
}

StageCycles& StageCycles::operator+=(const StageCycles& o) {
    processing += o.processing;
    communication += o.communication;
    wait += o.wait;
    bundles += o.bundles;
    ops += o.ops;
    processing_ops += o.processing_ops;
    units = o.units;
    words_received += o.words_received;
    words_sent += o.words_sent;
    modelled = modelled || o.modelled;
    return *this;
}

} // namespace nesshi::machine
