#include "kbuild/stage_machine.hpp"

#include "presets.hpp"

namespace nesshi::kbuild {

namespace detail {
const std::vector<isa::Machine>& presets() {
    static const std::vector<isa::Machine> all = [] { // every Options starts with three of them
        std::vector<isa::Machine> v;
        for (std::string_view name : isa::preset_names()) v.push_back(isa::load_machine(name));
        return v;
    }();
    return all;
}

const isa::Machine* preset(std::string_view name) {
    for (const isa::Machine& p : presets())
        if (p.name == name) return &p;
    return nullptr;
}
} // namespace detail

namespace {
isa::Machine load(std::string_view name_or_path) {
    if (const isa::Machine* p = detail::preset(name_or_path)) return *p;
    return isa::load_machine(name_or_path);
}
} // namespace

StageMachine::StageMachine(std::string_view name_or_path) : machine_(load(name_or_path)), reference_(name_or_path) {}

bool StageMachine::same_as_preset(std::string_view name) const {
    const isa::Machine* p = detail::preset(name);
    return p && p->same_as(machine_);
}

} // namespace nesshi::kbuild
