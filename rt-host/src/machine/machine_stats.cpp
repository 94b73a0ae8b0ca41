// Model names and the per-stage cycle sums.
#include "rt/machine.hpp"

namespace nesshi::rt {

const char* machine_model_name(MachineModel m) {
    switch (m) {
    case MachineModel::S: return "S";
    case MachineModel::M: return "M";
    case MachineModel::V: return "V";
    }
    return "?";
}

bool parse_machine_model(const std::string& s, MachineModel& out) {
    if (s == "S" || s == "s") out = MachineModel::S;
    else if (s == "M" || s == "m") out = MachineModel::M;
    else if (s == "V" || s == "v") out = MachineModel::V;
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

} // namespace nesshi::rt
