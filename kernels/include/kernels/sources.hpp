// The kernel sources (kernels/os, ic, seq and abi.inc), embedded in the library at build time, or
// read from a folder that overrides them (`--kernels DIR`).
//
//   const kernels::SourceSet src = kernels::embedded();      // or kernels::from_directory("my/kernels")
//   std::string_view text = src.text("os/dda.s");            // "# machine: os" ...
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace nesshi::kernels {

struct SourceFile {
    std::string path; // relative to the kernels folder: "os/dda.s", "abi.inc"
    std::string text;
};

// The kernels of a run, with where they came from ("built in" or the folder).
struct SourceSet {
    std::string origin;
    std::vector<SourceFile> files;
    // The text of `path`; throws std::runtime_error naming the origin when it is absent.
    const std::string& text(std::string_view path) const;
    bool has(std::string_view path) const;
};

// Generated at build time (cmake/EmbedFiles.cmake).
const std::vector<SourceFile>& embedded_sources();

SourceSet embedded();
// abi.inc, every */*.s and the sources they are scheduled from (*/*.pk) under `dir`, as embedded()
// holds them; throws std::runtime_error when dir holds no kernels.
SourceSet from_directory(const std::string& dir);

// The kernel a model runs on a stage: "os/dda.s", "ic/intersect.s", "seq/dda.s", "seq/intersect.s".
std::string kernel_path(bool vliw, bool intersect);

} // namespace nesshi::kernels
