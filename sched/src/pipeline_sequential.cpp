#include "pipeline_sequential.hpp"

#include "base/error.hpp"
#include "isa/ops.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <regex>

namespace nesshi::sched::pipe {

namespace {

std::string linear_loop(const Region& r, const std::vector<std::string>& placeholder_name, const isa::Machine& m,
                        const std::string& uid) {
    const int alu_lat = static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
    std::string o;
    o += fmt::format("        beqz {}, {}_lin_end\n", r.trip, uid);
    o += uid + "_lin:\n";
    for (const SrcOp& op : r.ops) {
        o += "        " + op_text(op, r, placeholder_name, 0) + "\n";
        for (std::uint32_t k = 1; k < m.latency_of(isa::kOps[op.opcode]); ++k) o += "        nop\n";
    }
    o += fmt::format("        addi {}, {}, -1\n", r.trip, r.trip);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    o += fmt::format("        bnez {}, {}_lin\n", r.trip, uid);
    o += uid + "_lin_end:\n";
    return o;
}

// A while loop's sequential meaning: the body up to its exit test, the test branching out, the
// rest; `count` counts the iterations that do not exit (verification reads it, never compares it).
std::string linear_while_loop(const Region& r, const std::vector<std::string>& placeholder_name, const isa::Machine& m,
                              const std::string& count, const std::string& uid) {
    const int alu_lat = static_cast<int>(m.latency[static_cast<std::size_t>(isa::OpClass::Alu)]);
    auto mv = [&](const std::string& to, const std::string& from) { // one copy, landed before the next op
        const bool f = from[0] == 'f';
        std::string t = f ? fmt::format("        fmov {}, {}\n", to, from) : fmt::format("        addi {}, {}, 0\n", to, from);
        for (std::uint32_t k = 1; k < m.latency[static_cast<std::size_t>(f ? isa::OpClass::FAdd : isa::OpClass::Alu)]; ++k)
            t += "        nop\n";
        return t;
    };
    auto placeholder_of = [&](const std::string& name) {
        return placeholder_name[static_cast<std::size_t>(r.virtual_index.at(name))];
    };
    std::string o;
    for (const auto& [name, c] : r.carry) o += mv(placeholder_of(name), c.in);
    for (const auto& [name, c] : r.carry) // OLD: the value each iteration starts with
        if (!c.old.empty()) o += mv(c.old, placeholder_of(name));
    o += fmt::format("        li {}, 0\n", count);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    o += uid + "_lin:\n";
    for (std::size_t k = 0; k < r.ops.size(); ++k) {
        SrcOp op = r.ops[k];
        if (static_cast<int>(k) == r.exit_op) op.operands.back() = uid + "_lin_end";
        o += "        " + op_text(op, r, placeholder_name, 0) + "\n";
        for (std::uint32_t j = 1; j < m.latency_of(isa::kOps[op.opcode]); ++j) o += "        nop\n";
    }
    o += fmt::format("        addi {0}, {0}, 1\n", count);
    for (int k = 1; k < alu_lat; ++k) o += "        nop\n";
    for (const auto& [name, c] : r.carry)
        if (!c.old.empty()) o += mv(c.old, placeholder_of(name));
    o += fmt::format("        jmp {}_lin\n", uid);
    o += uid + "_lin_end:\n";
    for (const auto& [name, c] : r.carry) o += mv(c.out, placeholder_of(name));
    for (const auto& [name, reg] : r.liveout) o += mv(reg, placeholder_of(name));
    return o;
}


// The virtuals each op of the region names, in operand order.
std::vector<std::vector<int>> virtuals_of_ops(const Region& r) {
    static const std::regex name(R"(%[A-Za-z_][A-Za-z0-9_]*)");
    std::vector<std::vector<int>> out;
    for (const SrcOp& op : r.ops) {
        std::vector<int>& vs = out.emplace_back();
        for (const std::string& operand : op.operands)
            for (auto it = std::sregex_iterator(operand.begin(), operand.end(), name); it != std::sregex_iterator(); ++it)
                if (const auto v = r.virtual_index.find(it->str()); v != r.virtual_index.end()) vs.push_back(v->second);
    }
    return out;
}

// The placeholder register of each virtual in the sequential meaning (`uses`: virtuals_of_ops):
// a free register of its own (the highest the file does not name) while there are enough; else virtuals whose lifetimes in
// one iteration do not meet share one (a virtual read before its definition, carried or live
// out is live throughout; the op of a last read never also defines the next owner, so the
// registers of one op stand for one virtual each).
std::vector<int> placeholder_registers(const Region& r, const std::vector<std::vector<int>>& uses,
                                       const std::set<std::pair<int, int>>& named, const isa::Machine& m,
                                       std::string_view filename) {
    std::vector<std::vector<int>> free(2);
    for (int f = 0; f < 2; ++f)
        for (int reg = static_cast<int>(m.regs[static_cast<std::size_t>(f)].count) - 1; reg >= 0; --reg)
            if (!named.count({f, reg})) free[static_cast<std::size_t>(f)].push_back(reg);
    const std::size_t nv = r.virtuals.size();
    std::vector<int> out(nv, -1);
    std::array<std::size_t, 2> need{};
    for (const Virtual& v : r.virtuals) ++need[static_cast<std::size_t>(v.file)];
    if (need[0] <= free[0].size() && need[1] <= free[1].size()) { // one each, as always
        std::array<std::size_t, 2> next{};
        for (std::size_t v = 0; v < nv; ++v) {
            const auto f = static_cast<std::size_t>(r.virtuals[v].file);
            out[v] = free[f][next[f]++];
        }
        return out;
    }
    const int n = static_cast<int>(r.ops.size());
    std::vector<int> first(nv, n), last(nv, -1);
    for (int i = 0; i < n; ++i)
        for (int v : uses[static_cast<std::size_t>(i)]) {
            first[static_cast<std::size_t>(v)] = std::min(first[static_cast<std::size_t>(v)], i);
            last[static_cast<std::size_t>(v)] = std::max(last[static_cast<std::size_t>(v)], i);
        }
    for (std::size_t v = 0; v < nv; ++v) {
        const Virtual& x = r.virtuals[v];
        if (first[v] < x.def || r.carry.count(x.name) || r.liveout.count(x.name)) first[v] = -1, last[v] = n;
        else first[v] = x.def;
    }
    std::vector<std::size_t> order(nv);
    for (std::size_t v = 0; v < nv; ++v) order[v] = v;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return first[a] < first[b]; });
    std::vector<std::vector<std::pair<int, int>>> busy(2); // (last op, register)
    std::vector<std::vector<int>> pool = free;
    for (auto& p : pool) std::reverse(p.begin(), p.end()); // taken from the back: the highest first
    for (std::size_t v : order) {
        const auto f = static_cast<std::size_t>(r.virtuals[v].file);
        auto& b = busy[f];
        for (auto it = b.begin(); it != b.end();)
            if (it->first < first[v]) pool[f].push_back(it->second), it = b.erase(it);
            else ++it;
        if (pool[f].empty()) fail(filename, static_cast<int>(r.begin + 1), "too many virtual registers");
        out[v] = pool[f].back();
        pool[f].pop_back();
        b.push_back({last[v], out[v]});
    }
    return out;
}

} // namespace

Sequential sequential_meaning(const Region& r, const std::set<std::pair<int, int>>& named, const isa::Machine& m,
                              std::string_view filename, const std::string& uid) {
    if (r.trip_reg >= static_cast<int>(m.regs[0].count)) fail(filename, static_cast<int>(r.begin + 1), "no such register");
    Sequential q;
    const std::vector<std::vector<int>> uses = virtuals_of_ops(r);
    const std::vector<int> regs = placeholder_registers(r, uses, named, m, filename);
    for (std::size_t v = 0; v < r.virtuals.size(); ++v) {
        const int f = static_cast<int>(r.virtuals[v].file);
        q.placeholders.insert({f, regs[v]});
        q.placeholder_name.push_back(reg_name(r.virtuals[v].file, regs[v]));
    }
    for (const std::vector<int>& vs : uses) {
        OpVirtuals& ov = q.op_virtuals.emplace_back();
        for (int v : vs) ov[{static_cast<int>(r.virtuals[static_cast<std::size_t>(v)].file), regs[static_cast<std::size_t>(v)]}] = v;
    }
    if (r.is_while) { // the lowest register neither named nor a placeholder counts iterations
        for (int reg = 1; reg < static_cast<int>(m.regs[0].count) && q.iteration_register.empty(); ++reg)
            if (!named.count({0, reg}) && !q.placeholders.count({0, reg})) q.iteration_register = reg_name(isa::RegFile::Int, reg);
        if (q.iteration_register.empty()) fail(filename, static_cast<int>(r.begin + 1), "too many virtual registers");
    }
    q.loop = r.is_while ? linear_while_loop(r, q.placeholder_name, m, q.iteration_register, uid)
                        : linear_loop(r, q.placeholder_name, m, uid);
    return q;
}

} // namespace nesshi::sched::pipe
