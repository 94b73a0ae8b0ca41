#include "kernels/sources.hpp"

#include "base/read_file.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace nesshi::kernels {

namespace fs = std::filesystem;

const std::string& SourceSet::text(std::string_view path) const {
    for (const SourceFile& f : files)
        if (f.path == path) return f.text;
    throw std::runtime_error("kernel source '" + std::string(path) + "' not found in " + origin);
}

bool SourceSet::has(std::string_view path) const {
    return std::any_of(files.begin(), files.end(), [&](const SourceFile& f) { return f.path == path; });
}

SourceSet embedded() { return {"the built-in kernels", embedded_sources()}; }

SourceSet from_directory(const std::string& dir) {
    SourceSet s{"'" + dir + "'", {}};
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw std::runtime_error("kernel folder '" + dir + "' does not exist");
    auto read = [&](const fs::path& p) {
        s.files.push_back({fs::relative(p, dir).generic_string(), base::read_file(p.string())});
    };
    if (fs::is_regular_file(fs::path(dir) / "abi.inc", ec)) read(fs::path(dir) / "abi.inc");
    std::vector<fs::path> kernels;
    for (const auto& sub : fs::directory_iterator(dir, ec)) {
        if (!sub.is_directory()) continue;
        for (const auto& f : fs::directory_iterator(sub.path(), ec))
            if (f.is_regular_file() && (f.path().extension() == ".s" || f.path().extension() == ".pk"))
                kernels.push_back(f.path());
    }
    std::sort(kernels.begin(), kernels.end());
    for (const auto& k : kernels) read(k);
    if (kernels.empty())
        throw std::runtime_error("'" + dir + "' holds no kernels (expected os/dda.s, ic/intersect.s, seq/*.s and abi.inc)");
    return s;
}

std::string kernel_path(bool vliw, bool intersect) {
    if (vliw) return intersect ? "ic/intersect.s" : "os/dda.s";
    return intersect ? "seq/intersect.s" : "seq/dda.s";
}

} // namespace nesshi::kernels
