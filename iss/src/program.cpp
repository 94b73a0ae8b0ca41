// Loading: decode every bundle once, check its static rules, and build the engine's form.
#include "iss/program.hpp"

#include "handlers.hpp"
#include "runtime_compile.hpp"

#include "iss/compiled.hpp"
#include "iss/memory.hpp"

#include "base/hash.hpp"

#include "isa/bundle_check.hpp"
#include "isa/printer.hpp"

#include <fmt/core.h>

#include <algorithm>

namespace nesshi::iss {

std::string reg_name(uint16_t flat) {
    if (flat >= kNumRegs) return "-";
    return fmt::format("{}{}", flat < isa::kMaxRegs ? 'r' : 'f', flat % isa::kMaxRegs);
}

namespace {

uint16_t reg_index(const isa::Instr& in, const isa::OpInfo& info, isa::Field f) {
    for (int i = 0; i < info.num_operands; ++i) {
        const isa::Operand& o = info.operands[i];
        bool reg = o.kind == isa::OperandKind::IntReg || o.kind == isa::OperandKind::FloatReg;
        if (o.kind == isa::OperandKind::Mem && f == isa::Field::Rs1) return flat_reg(isa::RegFile::Int, in.rs1);
        if (!reg || o.field != f) continue;
        auto file = o.kind == isa::OperandKind::IntReg ? isa::RegFile::Int : isa::RegFile::Float;
        return flat_reg(file, isa::field_value(in, f));
    }
    return kNoReg;
}

DecodedOp decode_op(const isa::Instr& in, const isa::Machine& m, uint32_t bundle, uint32_t index) {
    const isa::OpInfo& info = in.info();
    DecodedOp d;
    d.fn = d.fn_buffered = detail::kHandlers[in.opcode];
    d.dst = reg_index(in, info, isa::Field::Rd);
    d.a = reg_index(in, info, isa::Field::Rs1);
    d.b = reg_index(in, info, isa::Field::Rs2);
    d.c = reg_index(in, info, isa::Field::Rs3);
    d.imm = in.imm;
    d.latency = std::max<uint32_t>(1, m.latency_of(info)); // a result is never visible in its own cycle
    d.index = index;
    d.bundle = bundle;
    d.instr = in;
    return d;
}

} // namespace

Program::Program(const isa::ObjectFile& obj, const isa::Machine& m) : machine_(m), object_(obj) {
    if (!obj.machine.empty() && obj.machine != m.name)
        throw LoadError(fmt::format("object was assembled for machine '{}', not '{}'", obj.machine, m.name));
    if (obj.machine_fingerprint != 0 && obj.machine_fingerprint != m.fingerprint())
        throw LoadError(fmt::format("object was assembled for a different description of machine '{}' "
                                    "(fingerprint mismatch)", m.name));
    std::vector<std::vector<isa::Instr>> decoded;
    try {
        decoded = isa::decode_bundles(obj);
    } catch (const isa::ObjectError& e) {
        throw LoadError(e.loc(), e.message());
    }
    if (decoded.empty()) throw LoadError("object has no code");
    if (!obj.lines.empty() && obj.lines.size() != decoded.size())
        throw LoadError(fmt::format("line table has {} entries for {} bundles", obj.lines.size(), decoded.size()));
    for (const auto& le : obj.lines)
        if (le.file >= obj.files.size() && le.line != 0) throw LoadError("line table names a missing file");
    // Data must fit a memory region here, at load, as LoadError promises: the message is the one
    // MemorySystem::load_data would give each Processor (data_outside_memories), naming the machine.
    for (const auto& sec : obj.data)
        if (!sec.bytes.empty() && (sec.bytes.size() > UINT32_MAX || !m.memory_at(sec.address, uint32_t(sec.bytes.size()))))
            throw LoadError(data_outside_memories(m.memories, sec.address, sec.bytes.size(),
                                                  fmt::format("machine '{}' ({})", m.name, m.source)));

    for (uint32_t pc = 0; pc < decoded.size(); ++pc) {
        const auto& ops = decoded[pc];
        auto violations = isa::check_bundle(m, ops);
        if (!violations.empty()) {
            std::string msg = fmt::format("bundle {} breaks a static rule of machine '{}':", pc, m.name);
            for (const auto& v : violations)
                msg += fmt::format("\n  {}: {}", isa::rule_name(v.rule), v.message);
            throw LoadError(msg);
        }
        DecodedBundle b;
        b.first = uint32_t(ops_.size());
        b.count = uint32_t(ops.size());
        isa::BundleUsage u = isa::bundle_usage(ops);
        b.ops = u.ops;
        b.reads = u.reads;
        b.writes = u.writes;
        // Stores go last, so every load of the bundle reads memory as it was before the bundle.
        for (int pass = 0; pass < 2; ++pass)
            for (const isa::Instr& in : ops) {
                bool is_store = in.info().kind == isa::Kind::Store;
                if (is_store != (pass == 1)) continue;
                ops_.push_back(decode_op(in, m, pc, uint32_t(ops_.size())));
            }
        for (const isa::Instr& in : ops) {
            isa::Kind k = in.info().kind;
            if (k == isa::Kind::Recv || k == isa::Kind::Send) b.fifo = b.slow = true;
            if (k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink ||
                k == isa::Kind::JumpReg || k == isa::Kind::Halt)
                b.control = true;
            if (k != isa::Kind::Nop) b.slot_mask |= 1u << in.slot;
            if ((k == isa::Kind::Branch || k == isa::Kind::Jump || k == isa::Kind::JumpLink) &&
                in.imm >= decoded.size()) {
                // Not an error at load (the branch may never be taken); the engine traps it.
            }
        }
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            DecodedOp& d = ops_[i];
            if (d.dst == kNoReg || d.latency != 1) continue;
            ++b.lat1_writes[d.dst / isa::kMaxRegs];
            bool read_later = false;
            for (uint32_t j = i + 1; j < b.first + b.count; ++j)
                read_later |= ops_[j].a == d.dst || ops_[j].b == d.dst || ops_[j].c == d.dst;
            if (!read_later) d.fn = detail::kDirectHandlers[d.instr.opcode];
        }
        bundles_.push_back(b);
    }
    original_ = std::move(decoded);
    for (uint32_t pc = size(); pc-- > 0;) {
        DecodedBundle& b = bundles_[pc];
        if (!b.control && pc + 1 < size()) b.run = 1 + bundles_[pc + 1].run;
    }
    // Threaded form: each op's handler goes on to the next op; a bundle's last op also ends the
    // bundle (skipping the commit of queued latency-1 writes when it queues none, and the event
    // test when it has no load or store, the only ops that raise one before a run's last bundle).
    // Without a branch penalty, a control bundle (halt aside) goes on to the bundle it sends
    // control to, so a loop is one chain. A bundle before a FIFO bundle goes on into it only
    // when that bundle's fast gate passes (kEndGate).
    const bool jumps = m.branch_penalty == 0;
    for (uint32_t pc = 0; pc < size(); ++pc) {
        const DecodedBundle& b = bundles_[pc];
        int flags = pc + 1 < size() && bundles_[pc + 1].slow ? detail::kEndGate : 0;
        bool halt = false;
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            const DecodedOp& d = ops_[i];
            const isa::Kind k = d.instr.info().kind;
            halt |= k == isa::Kind::Halt;
            if (k == isa::Kind::Load || k == isa::Kind::Store) flags |= detail::kEndEvents;
            if (d.dst != kNoReg && d.latency == 1 && !detail::op_direct(d))
                flags |= detail::kEndCommit;
        }
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            DecodedOp& d = ops_[i];
            const int tail = i + 1 < b.first + b.count  ? detail::kNext
                             : b.control && !halt && jumps ? detail::kJump + (flags & detail::kEndCommit)
                             : b.run == 1                  ? detail::kExit
                                                           : detail::kEnd + flags;
            d.tfn = detail::threaded_handler(d.instr.opcode, detail::op_direct(d), tail);
        }
    }
    threaded_.reserve(ops_.size());
    for (const DecodedOp& d : ops_)
        threaded_.push_back(ThreadedOp{d.tfn, d.dst, d.a, d.b, d.c, d.imm, d.latency, d.index, d.bundle});

    // Channels: ids are 32-bit and sparse (a program may use channels 0 and 500000000), so each
    // send/recv gets the dense index of its id, and a processor keeps one slot per channel used.
    for (const DecodedOp& d : ops_)
        if (d.instr.info().kind == isa::Kind::Recv || d.instr.info().kind == isa::Kind::Send)
            channel_ids_.push_back(d.imm);
    std::sort(channel_ids_.begin(), channel_ids_.end());
    channel_ids_.erase(std::unique(channel_ids_.begin(), channel_ids_.end()), channel_ids_.end());
    for (DecodedOp& d : ops_)
        if (d.instr.info().kind == isa::Kind::Recv || d.instr.info().kind == isa::Kind::Send)
            d.chan = uint32_t(std::lower_bound(channel_ids_.begin(), channel_ids_.end(), d.imm) - channel_ids_.begin());
    // FIFO gates: per send/recv, the words its bundle moves through its channel in its direction
    // up to and including it (what the general gate asks of the channel for that op); per FIFO
    // bundle, the fast gate: those counts for each channel and direction, in the order of their
    // first op (EngineLoop::fifo_gate, chain.hpp gate_passes).
    for (DecodedBundle& b : bundles_) {
        if (!b.fifo) continue;
        b.gate_first = uint32_t(fifo_needs_.size());
        for (uint32_t i = b.first; i < b.first + b.count; ++i) {
            DecodedOp& d = ops_[i];
            const isa::Kind k = d.instr.info().kind;
            if (k != isa::Kind::Recv && k != isa::Kind::Send) continue;
            const bool recv = k == isa::Kind::Recv;
            auto g = std::find_if(fifo_needs_.begin() + b.gate_first, fifo_needs_.end(),
                                  [&](const FifoNeed& n) { return n.slot == d.chan && n.recv == recv; });
            if (g == fifo_needs_.end()) g = fifo_needs_.insert(g, FifoNeed{d.chan, 0, recv});
            d.need = uint16_t(++g->need);
        }
        b.gate_count = uint32_t(fifo_needs_.size()) - b.gate_first;
        // A direction whose words, more than one, all go through one channel moves them in one
        // Channel call (DecodedOp::batch).
        const auto first = fifo_needs_.begin() + b.gate_first;
        for (const bool recv : {true, false}) {
            const auto way = [&](const FifoNeed& n) { return n.recv == recv; };
            if (std::count_if(first, fifo_needs_.end(), way) != 1) continue;
            const uint32_t words = std::find_if(first, fifo_needs_.end(), way)->need;
            if (words < 2) continue;
            for (uint32_t i = b.first; i < b.first + b.count; ++i)
                if (ops_[i].instr.info().kind == (recv ? isa::Kind::Recv : isa::Kind::Send)) ops_[i].batch = uint16_t(words);
        }
    }

    // The key of a compiled-run table: every field the engine's form depends on.
    {
        base::Fnv1a h;
        auto add = [&h](uint64_t v) { h.add(std::string_view(reinterpret_cast<const char*>(&v), sizeof v)); };
        add(m.fingerprint());
        add(m.branch_penalty);
        add(bundles_.size());
        for (const DecodedBundle& b : bundles_) {
            add(b.first), add(b.count), add(b.run), add(b.slow), add(b.control), add(b.fifo);
            add(b.lat1_writes[0]), add(b.lat1_writes[1]), add(b.gate_first), add(b.gate_count);
        }
        for (const FifoNeed& g : fifo_needs_) add(g.slot), add(g.need), add(g.recv);
        for (const DecodedOp& d : ops_) {
            add(d.instr.opcode), add(d.dst), add(d.a), add(d.b), add(d.c), add(d.imm), add(d.latency);
            add(d.index), add(d.bundle), add(d.chan), add(d.need), add(detail::op_direct(d));
        }
        hash_ = h.value();
        compiled_ = find_compiled(hash_, size());
        if (!compiled_ && compiled_enabled()) runtime_ = detail::runtime_compiled_for(hash_, uint32_t(size()));
    }

    // Label regions, from code symbols sorted by address.
    for (const auto& s : object_.symbols)
        if (s.kind == isa::SymbolKind::Code && s.value < size()) code_labels_.push_back(&s);
    std::stable_sort(code_labels_.begin(), code_labels_.end(),
                     [](const isa::Symbol* a, const isa::Symbol* b) { return a->value < b->value; });
    region_index_.assign(size(), -1);
    // Code before the first label forms the "(entry)" region.
    uint32_t first_label = code_labels_.empty() ? size() : code_labels_.front()->value;
    if (first_label > 0) {
        for (uint32_t pc = 0; pc < first_label; ++pc) region_index_[pc] = 0;
        regions_.push_back({"(entry)", 0, first_label});
    }
    for (size_t i = 0; i < code_labels_.size(); ++i) {
        uint32_t first = code_labels_[i]->value;
        uint32_t end = i + 1 < code_labels_.size() ? code_labels_[i + 1]->value : size();
        if (end <= first) continue; // several labels on one bundle: the last one owns the region
        for (uint32_t pc = first; pc < end; ++pc) region_index_[pc] = int(regions_.size());
        regions_.push_back({code_labels_[i]->name, first, end});
    }
}

std::vector<isa::Instr> Program::bundle_instrs(uint32_t pc) const {
    return pc < original_.size() ? original_[pc] : std::vector<isa::Instr>{};
}

const CompiledProgram* Program::compiled() const {
    if (compiled_ || !runtime_) return compiled_;
    return detail::runtime_table(*runtime_);
}

const isa::Symbol* Program::find_symbol(std::string_view name) const {
    for (const auto& s : object_.symbols)
        if (s.name == name) return &s;
    return nullptr;
}

std::string Program::code_name(uint32_t pc) const {
    const isa::Symbol* best = nullptr;
    for (const isa::Symbol* s : code_labels_) {
        if (s->value > pc) break;
        best = s;
    }
    if (!best) return {};
    return best->value == pc ? best->name : fmt::format("{}+{}", best->name, pc - best->value);
}

std::string Program::source_of(uint32_t pc) const {
    if (pc >= object_.lines.size()) return {};
    const isa::LineEntry& le = object_.lines[pc];
    if (le.line == 0 || le.file >= object_.files.size()) return {};
    return fmt::format("{}:{}", object_.files[le.file], le.line);
}

std::string Program::format_op(const isa::Instr& in) const {
    return isa::format_instr_slotted(in, machine_, [this](uint32_t target) {
        for (const isa::Symbol* s : code_labels_)
            if (s->value == target) return s->name;
        return std::string();
    });
}

std::string Program::format_bundle(uint32_t pc) const {
    if (pc >= original_.size()) return "{ }";
    std::string out = "{ ";
    for (size_t i = 0; i < original_[pc].size(); ++i) {
        if (i) out += " ; ";
        out += format_op(original_[pc][i]);
    }
    return out + " }";
}

std::shared_ptr<const Program> load_program(const isa::ObjectFile& obj, const isa::Machine& m) {
    return std::make_shared<const Program>(obj, m);
}

std::shared_ptr<const Program> load_program_file(const std::string& path, const std::string& machine_override) {
    isa::ObjectFile obj;
    try {
        obj = isa::read_object_file(path);
    } catch (const isa::ObjectError& e) {
        throw LoadError(e.loc(), e.message());
    }
    std::string name = machine_override.empty() ? obj.machine : machine_override;
    if (name.empty()) throw LoadError(base::SourceLoc(path), "object names no machine; pass --machine");
    // A machine given by file when the object was assembled is known here by its name only (a
    // path recorded in the object would break when either moves): the user names the file again,
    // and the fingerprint checks that it is the same description.
    if (machine_override.empty() && !isa::is_preset(name))
        throw LoadError(base::SourceLoc(path),
                        fmt::format("assembled for machine '{}', which is not a preset: name its description with "
                                    "-m FILE (the object's fingerprint checks that it is the same machine)",
                                    name));
    isa::Machine m;
    try {
        m = isa::load_machine(name);
    } catch (const isa::MachineError& e) {
        throw LoadError(e.loc(), e.message());
    }
    try {
        return load_program(obj, m);
    } catch (const LoadError& e) {
        if (e.loc().known()) throw;
        throw LoadError(base::SourceLoc(path), e.message());
    }
}

} // namespace nesshi::iss
