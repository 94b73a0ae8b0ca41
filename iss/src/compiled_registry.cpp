// The registry of compiled-run tables (iss/compiled.hpp).
#include "iss/compiled.hpp"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace nesshi::iss {

namespace {
std::mutex registry_mutex;
std::vector<const CompiledProgram*>& registry() {
    static std::vector<const CompiledProgram*> r;
    return r;
}
std::atomic<bool>& enabled() {
    static std::atomic<bool> on = [] {
        const char* v = std::getenv("NESSHI_COMPILED");
        return !(v && std::strcmp(v, "0") == 0);
    }();
    return on;
}
} // namespace

void register_compiled(const CompiledProgram& p) {
    std::lock_guard lock(registry_mutex);
    for (const CompiledProgram* q : registry())
        if (q->hash == p.hash && q->bundles == p.bundles) return;
    registry().push_back(&p);
}

const CompiledProgram* find_compiled(uint64_t hash, uint32_t bundles) {
    if (!enabled()) return nullptr;
    std::lock_guard lock(registry_mutex);
    for (const CompiledProgram* q : registry())
        if (q->hash == hash && q->bundles == bundles) return q;
    return nullptr;
}

void set_compiled_enabled(bool on) { enabled() = on; }
bool compiled_enabled() { return enabled(); }

int compiled_count() {
    std::lock_guard lock(registry_mutex);
    return int(registry().size());
}

const CompiledProgram& compiled_at(int i) {
    std::lock_guard lock(registry_mutex);
    return *registry()[size_t(i)];
}

} // namespace nesshi::iss
