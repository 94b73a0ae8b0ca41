// Text and Chrome trace-event writers (see trace.hpp).
#include "iss/trace.hpp"

#include "isa/printer.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

namespace nesshi::iss {

std::string format_reg_value(uint16_t reg, uint32_t value) {
    if (reg >= isa::kMaxRegs) return fmt::format("{}={}", reg_name(reg), isa::format_float_bits(value));
    return fmt::format("{}={}", reg_name(reg), int32_t(value));
}

void TextTracer::on_cycle(const Program& prog, const CycleEvent& ev) {
    if (!header_) {
        fmt::print(out_, "{:>10} {:>6}  {:<7} {}\n", "cycle", "pc", "what", "bundle  => landed writes | ports");
        header_ = true;
    }
    const isa::Machine& m = prog.machine();
    std::array<uint32_t, isa::kNumRegFiles> writes{};
    std::string landed;
    for (const PendingWrite& w : *ev.landed) {
        landed += (landed.empty() ? "" : " ") + format_reg_value(w.reg, w.value);
        ++writes[(w.reg >> 7) & 1];
    }
    std::string text, ports;
    const char* what = ev.what == CycleEvent::Issue ? "issue" : ev.what == CycleEvent::Wait ? "wait" : "bubble";
    if (ev.what != CycleEvent::Bubble) {
        std::string name = prog.code_name(ev.pc);
        text = (name.empty() ? "" : name + " ") + prog.format_bundle(ev.pc);
    }
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        uint32_t reads = ev.what == CycleEvent::Issue ? prog.bundles()[ev.pc].reads[f] : 0;
        ports += fmt::format("{}{} r{}/{} w{}/{}", f ? " " : "", isa::kRegFileNames[f], reads, m.regs[f].read_ports,
                             writes[f], m.regs[f].write_ports);
    }
    fmt::print(out_, "{:>10} {:>6}  {:<7} {}  => {}{}| {}\n", ev.cycle, ev.pc, what, text, landed,
               landed.empty() ? "" : " ", ports);
}

void ChromeTracer::event(const std::string& json) {
    fmt::print(out_, "{}\n{}", first_ ? "" : ",", json);
    first_ = false;
}

void ChromeTracer::on_cycle(const Program& prog, const CycleEvent& ev) {
    using nlohmann::json;
    const isa::Machine& m = prog.machine();
    if (!started_) {
        started_ = true;
        fmt::print(out_, "{{\"displayTimeUnit\": \"ns\", \"traceEvents\": [");
        for (size_t s = 0; s <= m.slots.size(); ++s) {
            std::string name = s < m.slots.size() ? m.slots[s].name : "stall";
            event(json{{"name", "thread_name"}, {"ph", "M"}, {"pid", 1}, {"tid", s}, {"args", {{"name", name}}}}.dump());
        }
    }
    if (ev.what != CycleEvent::Issue) {
        event(json{{"name", ev.what == CycleEvent::Wait ? "wait" : "bubble"}, {"ph", "X"}, {"ts", ev.cycle},
                   {"dur", 1}, {"pid", 1}, {"tid", m.slots.size()}, {"args", {{"pc", ev.pc}}}}
                  .dump());
        return;
    }
    std::string label = prog.code_name(ev.pc);
    for (const isa::Instr& in : prog.bundle_instrs(ev.pc)) {
        if (in.info().kind == isa::Kind::Nop) continue;
        event(json{{"name", std::string(in.info().mnemonic)},
                   {"cat", std::string(isa::kOpClassNames[int(in.info().cls)])},
                   {"ph", "X"}, {"ts", ev.cycle}, {"dur", 1}, {"pid", 1}, {"tid", in.slot},
                   {"args", {{"op", isa::format_instr(in)}, {"pc", ev.pc}, {"label", label}}}}
                  .dump());
    }
}

void ChromeTracer::finish() {
    if (finished_) return;
    finished_ = true;
    if (!started_) fmt::print(out_, "{{\"displayTimeUnit\": \"ns\", \"traceEvents\": [");
    fmt::print(out_, "\n]}}\n"); // the owner of out_ flushes and checks it (base::OutputFile::close)
}

} // namespace nesshi::iss
