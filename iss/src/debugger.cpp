// The debugger's command table and commands (see debugger.hpp).
#include "iss/debugger.hpp"

#include "iss/stats.hpp"
#include "iss/trace.hpp"

#include "isa/printer.hpp"

#include <algorithm>
#include <charconv>
#include <map>

namespace nesshi::iss {

namespace {

std::vector<std::string> split(std::string_view line) {
    std::vector<std::string> out;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        if (j > i) out.emplace_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

std::optional<int64_t> number(std::string_view t) {
    bool neg = !t.empty() && t[0] == '-';
    if (neg) t.remove_prefix(1);
    int base = 10;
    if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
        base = 16;
        t.remove_prefix(2);
    }
    uint64_t v = 0;
    auto r = std::from_chars(t.data(), t.data() + t.size(), v, base);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || v > 0xffffffffull) return std::nullopt;
    return neg ? -int64_t(v) : int64_t(v);
}

std::optional<uint16_t> register_index(std::string_view t) {
    if (t.size() < 2 || (t[0] != 'r' && t[0] != 'f')) return std::nullopt;
    auto n = number(t.substr(1));
    if (!n || *n < 0 || *n >= isa::kMaxRegs) return std::nullopt;
    return flat_reg(t[0] == 'r' ? isa::RegFile::Int : isa::RegFile::Float, uint32_t(*n));
}

// The most arguments a command's usage takes: words of its longest alternative ("regs [r|f|p] |
// inflight": 2; "[/N] ADDR": 2; "": 0).
std::size_t max_args(std::string_view usage) {
    std::size_t most = 0;
    while (true) {
        const std::size_t bar = usage.find(" | ");
        const std::vector<std::string> words = split(usage.substr(0, bar));
        most = std::max(most, words.size());
        if (bar == std::string_view::npos) return most;
        usage.remove_prefix(bar + 3);
    }
}

} // namespace

const std::vector<DebugCommand>& Debugger::commands() {
    static const std::vector<DebugCommand> table = {
        {"step", {"s", "si"}, "[N]", "issue N bundles (default 1); Enter repeats the last step", &Debugger::cmd_step},
        {"continue", {"c"}, "", "run to a breakpoint, a watch change, halt or fault (Ctrl-C stops it)", &Debugger::cmd_continue},
        {"run", {"r"}, "", "restart the program, then continue (breakpoints and watches stay)", &Debugger::cmd_run},
        {"restart", {}, "", "back to the loaded program: pc 0, cycle 0, registers zero, data and inputs reloaded", &Debugger::cmd_restart},
        {"until", {"u"}, "LOC", "run until the bundle at LOC is next to issue", &Debugger::cmd_until},
        {"break", {"b"}, "LOC", "stop before the bundle at LOC issues (label or bundle address)", &Debugger::cmd_break},
        {"delete", {"d"}, "[ID]", "delete breakpoint or watch ID (all when omitted)", &Debugger::cmd_delete},
        {"watch", {"w"}, "REG|ADDR", "stop when a register or the memory word at ADDR changes", &Debugger::cmd_watch},
        {"info", {"i"}, "regs [r|f|p] | inflight | ports | break",
         "registers (r: integer, f: float, p: pc/cycle/status), pending writes, port use, breakpoints",
         &Debugger::cmd_info},
        {"x", {}, "[/N] ADDR", "examine N memory words from ADDR (x/4 buf)", &Debugger::cmd_examine},
        {"disas", {"l", "list"}, "[LOC]", "disassemble bundles around LOC (default: the next bundle)", &Debugger::cmd_disas},
        {"print", {"p"}, "VALUE", "print a register, label or number in hex, decimal and float", &Debugger::cmd_print},
        {"stats", {}, "", "statistics so far", &Debugger::cmd_stats},
        {"help", {"h", "?"}, "[COMMAND]", "list commands, or describe one", &Debugger::cmd_help},
        {"quit", {"q", "exit"}, "", "end the session", &Debugger::cmd_quit},
    };
    return table;
}

Debugger::Debugger(Processor& p, std::FILE* out) : p_(p), out_(out) {}

bool Debugger::execute(std::string_view line) {
    std::vector<std::string> words = split(line);
    if (words.empty()) words = last_step_; // Enter, or a line of blanks, repeats the last step
    if (words.empty() || words[0][0] == '#') return !quit_;
    // "x/4 ADDR": split the count off the command name.
    std::string name = words[0];
    std::vector<std::string> args(words.begin() + 1, words.end());
    if (name.size() > 1 && name[0] == 'x' && name[1] == '/') {
        std::vector<std::string> with_count{name.substr(1)};
        with_count.insert(with_count.end(), args.begin(), args.end());
        args = std::move(with_count);
        name.resize(1); // "x"
    }
    for (const DebugCommand& c : commands()) {
        bool match = c.name == name || std::find(c.aliases.begin(), c.aliases.end(), name) != c.aliases.end();
        if (!match) continue;
        // More arguments than the command takes is an error, never ignored ("break loop if r1 == 5"
        // would stop at every pass, the condition dropped).
        if (const std::size_t most = max_args(c.args); args.size() > most) {
            std::string extra;
            for (std::size_t k = most; k < args.size(); ++k) extra += (extra.empty() ? "" : " ") + args[k];
            say("{}: unexpected '{}' (usage: {}{}{}); nothing done\n", c.name, extra, c.name, c.args.empty() ? "" : " ",
                c.args);
            return !quit_;
        }
        if (c.run == &Debugger::cmd_step) last_step_ = words; // what ran, never the raw line (" " has no words)
        (this->*c.run)(args);
        std::fflush(out_);
        return !quit_;
    }
    say("unknown command '{}'; try 'help'\n", name);
    return !quit_;
}

std::optional<uint32_t> Debugger::value(std::string_view tok) {
    if (auto r = register_index(tok)) return p_.reg(*r);
    if (auto n = number(tok)) return uint32_t(*n);
    std::string_view base = tok;
    int64_t off = 0;
    if (size_t k = tok.find_first_of("+-", 1); k != std::string_view::npos) {
        auto n = number(tok.substr(k + 1));
        if (!n) {
            say("bad offset in '{}'\n", tok);
            return std::nullopt;
        }
        off = tok[k] == '-' ? -*n : *n;
        base = tok.substr(0, k);
    }
    if (const isa::Symbol* s = p_.program().find_symbol(base)) return uint32_t(int64_t(s->value) + off);
    say("no register, label or number named '{}'\n", tok);
    return std::nullopt;
}

std::optional<uint32_t> Debugger::location(std::string_view tok) {
    auto v = value(tok);
    if (!v) return std::nullopt;
    if (*v >= p_.program().size()) {
        say("{} is not a bundle address (0..{})\n", tok, p_.program().size() - 1);
        return std::nullopt;
    }
    return v;
}

std::string Debugger::loc_text(uint32_t pc) const {
    const Program& prog = p_.program();
    std::string name = prog.code_name(pc), src = prog.source_of(pc);
    std::string out = fmt::format("pc {}", pc);
    if (!name.empty()) out += fmt::format(" ({})", name);
    if (!src.empty()) out += fmt::format(" at {}", src);
    return out;
}

void Debugger::where() {
    say("cycle {}, {}\n", p_.cycle(), loc_text(p_.pc()));
    if (p_.status() == Status::Running || p_.status() == Status::Blocked)
        say("  next: {}\n", p_.program().format_bundle(p_.pc()));
}

bool Debugger::finished() {
    switch (p_.status()) {
    case Status::Halted: say("halted after {} cycles\n", p_.cycle()); return true;
    case Status::Faulted: say("{}", p_.fault_report()); return true;
    case Status::Blocked: say("blocked on channel {}\n", p_.blocked_channel()); return true;
    case Status::Running: return false;
    }
    return false;
}

bool Debugger::read_watch(const Watch& w, uint32_t& v) const {
    if (w.is_reg) {
        v = p_.reg(uint16_t(w.where));
        return true;
    }
    return p_.memory().peek(w.where, 4, v);
}

void Debugger::run_until(const std::function<bool()>& stop, bool stop_at_breaks) {
    if (p_.status() == Status::Halted || p_.status() == Status::Faulted) {
        finished();
        return;
    }
    uint64_t start = p_.cycle();
    bool first = true;
    while (true) {
        if (!first && stop_at_breaks) {
            auto hit = std::find_if(breaks_.begin(), breaks_.end(), [&](auto& b) { return b.second == p_.pc(); });
            if (hit != breaks_.end()) {
                say("breakpoint {}: ", hit->first);
                break;
            }
        }
        if (!first && stop()) break;
        if (interrupt.exchange(false, std::memory_order_relaxed)) {
            say("interrupted: ");
            break;
        }
        first = false;
        p_.step(1, max_cycles - (p_.cycle() - start)); // the limit holds inside a step (a long wait) too
        bool changed = false;
        for (auto& [id, w] : watches_) {
            uint32_t v = 0;
            if (read_watch(w, v) && v != w.last) {
                std::string what = w.is_reg ? reg_name(uint16_t(w.where)) : fmt::format("mem[0x{:08x}]", w.where);
                say("watch {}: {} changed from {} to {}\n", id, what, int32_t(w.last), int32_t(v));
                w.last = v;
                changed = true;
            }
        }
        if (changed || finished()) break;
        if (p_.cycle() - start >= max_cycles) {
            say("stopped after {} cycles (limit)\n", max_cycles);
            break;
        }
    }
    where();
}

void Debugger::cmd_step(const std::vector<std::string>& a) {
    uint64_t n = 1;
    if (!a.empty()) {
        if (auto k = number(a[0]); k && *k < 0) { // as a value, -1 would be 2^32 - 1 bundles
            say("step takes a count of 0 or more, not {}\n", a[0]);
            return;
        }
        auto v = value(a[0]);
        if (!v) return;
        n = *v;
    }
    if (n == 0) return; // nothing to issue
    uint64_t done = 0;
    run_until([&] { return ++done >= n; }, false);
}

void Debugger::cmd_continue(const std::vector<std::string>&) {
    run_until([] { return false; }, true);
}

void Debugger::restart() {
    p_.reset();
    if (on_restart) on_restart();
    for (auto& [id, w] : watches_) read_watch(w, w.last);
    interrupt.store(false, std::memory_order_relaxed);
    std::string kept;
    if (!breaks_.empty() || !watches_.empty())
        kept = fmt::format(" ({} breakpoint{} and {} watch{} kept)", breaks_.size(), breaks_.size() == 1 ? "" : "s",
                           watches_.size(), watches_.size() == 1 ? "" : "es");
    say("restarted{}\n", kept);
}

void Debugger::cmd_restart(const std::vector<std::string>&) {
    restart();
    where();
}

void Debugger::cmd_run(const std::vector<std::string>& a) {
    restart();
    // From pc 0 a breakpoint there stops before anything issues, as a fresh start should.
    auto hit = std::find_if(breaks_.begin(), breaks_.end(), [&](auto& b) { return b.second == p_.pc(); });
    if (hit != breaks_.end()) {
        say("breakpoint {}: ", hit->first);
        where();
        return;
    }
    cmd_continue(a);
}

void Debugger::cmd_until(const std::vector<std::string>& a) {
    if (a.empty()) {
        say("until needs a location\n");
        return;
    }
    auto loc = location(a[0]);
    if (!loc) return;
    run_until([&] { return p_.pc() == *loc; }, true);
}

void Debugger::cmd_break(const std::vector<std::string>& a) {
    if (a.empty()) {
        info_breaks();
        return;
    }
    auto loc = location(a[0]);
    if (!loc) return;
    breaks_.push_back({next_id_, *loc});
    say("breakpoint {} at {}\n", next_id_++, loc_text(*loc));
}

void Debugger::cmd_delete(const std::vector<std::string>& a) {
    if (a.empty()) {
        breaks_.clear();
        watches_.clear();
        say("deleted all breakpoints and watches\n");
        return;
    }
    auto id = number(a[0]);
    size_t before = breaks_.size() + watches_.size();
    if (id) {
        std::erase_if(breaks_, [&](auto& b) { return b.first == *id; });
        std::erase_if(watches_, [&](auto& w) { return w.first == *id; });
    }
    if (breaks_.size() + watches_.size() == before) say("no breakpoint or watch {}\n", a[0]);
    else say("deleted {}\n", a[0]);
}

void Debugger::cmd_watch(const std::vector<std::string>& a) {
    if (a.empty()) {
        say("watch needs a register or address\n");
        return;
    }
    Watch w;
    if (auto r = register_index(a[0])) {
        w.where = *r;
    } else {
        auto addr = value(a[0]);
        if (!addr) return;
        w.is_reg = false;
        w.where = *addr;
        if (!p_.memory().peek(w.where, 4, w.last)) {
            say("0x{:08x} is outside every memory region\n", w.where);
            return;
        }
    }
    read_watch(w, w.last);
    std::string what = w.is_reg ? reg_name(uint16_t(w.where)) : fmt::format("mem[0x{:08x}]", w.where);
    say("watch {}: {} (now {})\n", next_id_, what, int32_t(w.last));
    watches_.push_back({next_id_++, w});
}

void Debugger::info_regs(char which) {
    if (which == 'p') {
        say("pc {}  cycle {}  status {}\n", p_.pc(), p_.cycle(), status_name(p_.status()));
        return;
    }
    bool is_float = which == 'f';
    std::string line;
    int shown = 0, zero = 0;
    for (uint32_t n = 0; n < isa::kMaxRegs; ++n) {
        uint16_t r = flat_reg(is_float ? isa::RegFile::Float : isa::RegFile::Int, n);
        uint32_t v = p_.reg(r);
        if (v == 0) {
            ++zero;
            continue;
        }
        std::string cell = format_reg_value(r, v);
        line += fmt::format("{:<18}", cell);
        if (++shown % 4 == 0) {
            say("  {}\n", line);
            line.clear();
        }
    }
    if (!line.empty()) say("  {}\n", line);
    say("  ({} {} registers are zero)\n", zero, is_float ? "float" : "integer");
}

void Debugger::info_inflight() {
    auto pending = p_.inflight();
    if (pending.empty()) {
        say("no writes in flight at cycle {}\n", p_.cycle());
        return;
    }
    const Program& prog = p_.program();
    say("{} write{} in flight at cycle {}:\n", pending.size(), pending.size() == 1 ? "" : "s", p_.cycle());
    for (const PendingWrite& w : pending) {
        const DecodedOp& d = prog.ops()[w.op];
        say("  {:<16} lands in cycle {} (+{})  from {} (bundle {}, issued in cycle {})\n",
            format_reg_value(w.reg, w.value), w.lands, w.lands - p_.cycle(), isa::format_instr(d.instr), d.bundle,
            w.lands - d.latency);
    }
}

void Debugger::info_ports() {
    const Program& prog = p_.program();
    const isa::Machine& m = prog.machine();
    uint32_t pc = p_.pc();
    const DecodedBundle& b = prog.bundles()[pc];
    say("bundle {}: {}\n", pc, prog.format_bundle(pc));
    // Writes by landing cycle: this bundle's, plus those already in flight.
    std::map<uint64_t, std::array<uint32_t, 2>> own, flying;
    for (uint32_t i = b.first; i < b.first + b.count; ++i) {
        const DecodedOp& d = prog.ops()[i];
        if (d.dst != kNoReg) ++own[p_.cycle() + d.latency][d.dst / isa::kMaxRegs];
    }
    for (const PendingWrite& w : p_.inflight()) ++flying[w.lands][w.reg / isa::kMaxRegs];
    for (int f = 0; f < isa::kNumRegFiles; ++f) {
        std::string writes;
        for (auto& [t, n] : own) {
            if (!n[f]) continue;
            uint32_t total = n[f] + (flying.count(t) ? flying[t][f] : 0);
            writes += fmt::format("  cycle {}: {} of {}{}", t, total, m.regs[f].write_ports,
                                  total > n[f] ? fmt::format(" ({} in flight)", total - n[f]) : "");
        }
        say("  {:<5} reads {} of {}{}{}\n", isa::kRegFileNames[f], b.reads[f], m.regs[f].read_ports,
            writes.empty() ? "" : ";  writes landing:", writes);
    }
}

void Debugger::info_breaks() {
    if (breaks_.empty() && watches_.empty()) say("no breakpoints or watches\n");
    for (auto& [id, pc] : breaks_) say("  {}: break at {}\n", id, loc_text(pc));
    for (auto& [id, w] : watches_)
        say("  {}: watch {}\n", id, w.is_reg ? reg_name(uint16_t(w.where)) : fmt::format("mem[0x{:08x}]", w.where));
}

void Debugger::cmd_info(const std::vector<std::string>& a) {
    std::string what = a.empty() ? "" : a[0];
    if (what == "regs" || what == "r" || what == "registers") {
        std::string which = a.size() > 1 ? a[1] : "";
        if (which.empty()) {
            info_regs('p');
            info_regs('r');
            info_regs('f');
        } else if (which == "r" || which == "f" || which == "p") {
            info_regs(which[0]);
        } else {
            say("info regs takes r, f or p\n");
        }
    } else if (what == "inflight" || what == "pending") {
        info_inflight();
    } else if (what == "ports") {
        info_ports();
    } else if (what == "break" || what == "breaks" || what == "watch") {
        info_breaks();
    } else {
        say("info what? regs [r|f|p], inflight, ports, break\n");
    }
}

void Debugger::cmd_examine(const std::vector<std::string>& a) {
    uint32_t n = 1;
    size_t at = 0;
    if (!a.empty() && a[0][0] == '/') {
        auto c = number(std::string_view(a[0]).substr(1));
        if (!c || *c <= 0 || *c > 4096) {
            say("bad count '{}'\n", a[0]);
            return;
        }
        n = uint32_t(*c);
        at = 1;
    }
    if (a.size() <= at) {
        say("x needs an address\n");
        return;
    }
    auto addr = value(a[at]);
    if (!addr) return;
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t where = *addr + 4 * i, v = 0;
        if (!p_.memory().peek(where, 4, v)) {
            say("0x{:08x}: outside every memory region\n", where);
            return;
        }
        say("0x{:08x}: 0x{:08x}  {:>11}  {}\n", where, v, int32_t(v), isa::format_float_bits(v));
    }
}

void Debugger::cmd_disas(const std::vector<std::string>& a) {
    const Program& prog = p_.program();
    uint32_t center = p_.pc();
    if (!a.empty()) {
        auto loc = location(a[0]);
        if (!loc) return;
        center = *loc;
    }
    uint32_t first = center >= 2 ? center - 2 : 0;
    uint32_t end = std::min<uint32_t>(prog.size(), first + 8);
    for (uint32_t pc = first; pc < end; ++pc) {
        std::string name = prog.code_name(pc);
        if (!name.empty() && name.find('+') == std::string::npos) say("{}:\n", name);
        say("{} {:>5}  {}\n", pc == p_.pc() ? "=>" : "  ", pc, prog.format_bundle(pc));
    }
}

void Debugger::cmd_print(const std::vector<std::string>& a) {
    if (a.empty()) {
        say("print needs a value\n");
        return;
    }
    for (const std::string& t : a) {
        auto v = value(t);
        if (!v) return;
        say("{} = 0x{:08x}  {}  {}\n", t, *v, int32_t(*v), isa::format_float_bits(*v));
    }
}

void Debugger::cmd_stats(const std::vector<std::string>&) { say("{}", stats_text(compute_stats(p_))); }

void Debugger::cmd_help(const std::vector<std::string>& a) {
    for (const DebugCommand& c : commands()) {
        if (!a.empty() && c.name != a[0] && std::find(c.aliases.begin(), c.aliases.end(), a[0]) == c.aliases.end())
            continue;
        std::string names(c.name);
        for (auto al : c.aliases) names += fmt::format(", {}", al);
        say("  {:<22} {:<14} {}\n", names, c.args, c.help);
    }
    if (a.empty())
        say("Values: numbers (12, 0x1f), labels (loop, buf+8) and registers (r3, f1) work wherever a value\n"
            "or address is expected.\n");
}

std::vector<std::string> Debugger::complete(std::string_view line) const {
    size_t start = line.find_last_of(" \t") == std::string_view::npos ? 0 : line.find_last_of(" \t") + 1;
    std::string_view word = line.substr(start);
    std::vector<std::string> before = split(line.substr(0, start));
    std::vector<std::string> all;
    if (before.empty()) {
        for (const DebugCommand& c : commands()) all.emplace_back(c.name);
    } else if (before.size() == 1 && (before[0] == "info" || before[0] == "i")) {
        all = {"regs", "inflight", "ports", "break"};
    } else if (before.size() == 1 && (before[0] == "help" || before[0] == "h" || before[0] == "?")) {
        for (const DebugCommand& c : commands()) all.emplace_back(c.name);
    } else {
        for (uint32_t n = 0; n < isa::kMaxRegs; ++n) {
            all.push_back(fmt::format("r{}", n));
            all.push_back(fmt::format("f{}", n));
        }
        for (const isa::Symbol& sym : p_.program().object().symbols) all.push_back(sym.name);
    }
    std::vector<std::string> out;
    for (std::string& c : all)
        if (c.starts_with(word)) out.push_back(std::move(c));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void Debugger::cmd_quit(const std::vector<std::string>&) { quit_ = true; }

} // namespace nesshi::iss
