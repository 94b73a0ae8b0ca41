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

using assembler::header_machine;

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
