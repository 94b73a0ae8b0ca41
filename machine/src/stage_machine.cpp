#include "machine/stage_machine.hpp"

#include <map>
#include <mutex>

namespace nesshi::machine {

namespace {
// The presets, parsed once per process: every Options starts with three of them.
const isa::Machine* preset(std::string_view name) {
    if (!isa::is_preset(name)) return nullptr;
    static std::mutex mutex;
    static std::map<std::string, isa::Machine, std::less<>> loaded;
    std::lock_guard lock(mutex);
    auto it = loaded.find(name);
    if (it == loaded.end()) it = loaded.emplace(std::string(name), isa::load_machine(name)).first;
    return &it->second;
}
} // namespace

StageMachine::StageMachine(std::string_view name_or_path)
    : machine_(preset(name_or_path) ? *preset(name_or_path) : isa::load_machine(name_or_path)), reference_(name_or_path) {}

bool StageMachine::same_as_preset(std::string_view name) const {
    const isa::Machine* p = preset(name);
    return p && p->same_as(machine_);
}

} // namespace nesshi::machine
