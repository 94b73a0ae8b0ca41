// The one way the tools read a whole input file: regular files only, and never more than a cap.
//
//   std::string text = base::read_file(path);                          // sources, scenes, objects...
//   std::string toml = base::read_file(path, base::kMaxMachineFileBytes);
//
// A directory, a device (/dev/zero), a named pipe or a socket is refused before anything is
// read (a pipe is opened without blocking), and so is a file above the cap; the error is a
// base::Error located at the path: "is a directory", "not a regular file",
// "file too large (N bytes; the limit is M)", "cannot open: <the system's reason>" or
// "cannot read: <reason>". /dev/null, the
// usual empty input, reads as an empty file.
#pragma once

#include <cstddef>
#include <string>

namespace nesshi::base {

// Sources (.s, .sa, includes), scenes, objects, word files, debugger scripts: 256 MiB, far above
// any real input (the largest scene we render is a few MiB) and far below what exhausts memory.
inline constexpr std::size_t kMaxInputFileBytes = std::size_t{256} << 20;
// Machine descriptions are about 1 KB; 1 MiB leaves room for comments and still refuses junk.
inline constexpr std::size_t kMaxMachineFileBytes = std::size_t{1} << 20;

// The whole contents of the regular file at `path` (binary, unchanged). Throws base::Error.
std::string read_file(const std::string& path, std::size_t max_bytes = kMaxInputFileBytes);

} // namespace nesshi::base
