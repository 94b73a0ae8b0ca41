// Helpers shared by the assembler tests.
#pragma once

#include "assembler/assembler.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace nesshi::test {

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The machine named by a `# machine: NAME` first line, or empty.
inline std::string header_machine(const std::string& text) {
    const std::string key = "# machine:";
    if (text.rfind(key, 0) != 0) return {};
    auto end = text.find('\n');
    std::string m = text.substr(key.size(), end == std::string::npos ? std::string::npos : end - key.size());
    m.erase(0, m.find_first_not_of(" \t"));
    m.erase(m.find_last_not_of(" \t\r") + 1);
    return m;
}

// examples/**/*.s that declare their machine (kernels/ are covered by the CTest round trips,
// registered per file in tests/assembler/CMakeLists.txt).
inline std::vector<std::filesystem::path> asm_programs() {
    namespace fs = std::filesystem;
    std::vector<fs::path> out;
    for (const char* dir : {"examples"}) {
        fs::path root = fs::path(NESSHI_SOURCE_DIR) / dir;
        if (!fs::exists(root)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root))
            if (e.is_regular_file() && e.path().extension() == ".s" && !header_machine(read_text(e.path())).empty())
                out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

inline assembler::AsmResult assemble(const std::string& text, const std::string& machine = "os") {
    return assembler::assemble_string(text, "test.s", isa::load_machine(machine), {});
}

} // namespace nesshi::test
