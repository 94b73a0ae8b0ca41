// Fuzz target `object`: object-file bytes (the trailing CRC is recomputed, so mutations reach
// past the checksum) through the reader, the decoder, the ISS loader and the disassembler on the
// machine the object names (os when it names none we have). Bad input is a base::Error, never a
// crash; whatever disassembles re-assembles, unless only timing across bundles forbids it, or
// the object holds data outside the machine's memories (which the loader refuses too).
#include "check.hpp"

#include "assembler/assembler.hpp"
#include "isa/object.hpp"
#include "iss/program.hpp"

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace nesshi;

namespace {

// The disassembler checks each bundle's rules, not timing across bundles (latencies, write ports
// per landing cycle), which the ISS's checked engine reports when the code runs; so a foreign
// object may disassemble into text the assembler refuses for those reasons, and only for those;
// and, when the ISS refused to load it (`loads` false), for data that fits no memory region.
bool only_timing_errors(const std::string& diagnostics, bool loads) {
    std::size_t at = 0;
    while ((at = diagnostics.find(": error: ", at)) != std::string::npos) {
        const std::string line = diagnostics.substr(at, diagnostics.find('\n', at) - at);
        if (line.find("is read before its new value lands") == std::string::npos &&
            line.find("is written twice in one cycle") == std::string::npos &&
            line.find("is written before an earlier write to it lands") == std::string::npos &&
            line.find("writes land in one cycle") == std::string::npos &&
            (loads || line.find("does not fit in a memory region") == std::string::npos))
            return false;
        ++at;
    }
    return diagnostics.find(": error: ") != std::string::npos;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::uint8_t> bytes(data, data + size);
    if (bytes.size() >= 4) {
        const std::uint32_t crc = isa::crc32(bytes.data(), bytes.size() - 4);
        for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + std::size_t(i)] = std::uint8_t(crc >> (8 * i));
    }
    isa::ObjectFile obj;
    try {
        obj = isa::read_object(bytes, "fuzz.o");
    } catch (const base::Error&) {
        return 0;
    }
    const isa::Machine m = isa::load_machine(isa::is_preset(obj.machine) ? std::string(obj.machine) : "os");
    try {
        (void)isa::decode_bundles(obj);
    } catch (const base::Error&) {
    }
    bool loads = true;
    try {
        (void)iss::load_program(obj, m);
    } catch (const base::Error&) {
        loads = false;
    }
    std::string dis;
    try {
        dis = assembler::disassemble(obj, m);
    } catch (const base::Error&) {
        return 0;
    }
    const assembler::AsmResult r = assembler::assemble_string(dis, "dis.s", m, {});
    fuzz::check(r.ok || only_timing_errors(r.diagnostics, loads), "a disassembled object re-assembles", dis + r.diagnostics);
    return 0;
}
