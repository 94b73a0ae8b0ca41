# Writes machine_presets.hpp: each isa/machines/*.toml as a string, so presets are embedded
# copies of the files in the repository (run at build time whenever a .toml changes).
file(GLOB files "${SRC_DIR}/*.toml")
list(SORT files)
set(body "// Generated from isa/machines/*.toml by embed_presets.cmake; do not edit.\n#pragma once\n#include <string_view>\nnamespace nesshi::isa {\nstruct Preset { std::string_view name; std::string_view text; };\ninline constexpr Preset kPresets[] = {\n")
foreach(f ${files})
  get_filename_component(name "${f}" NAME_WE)
  file(READ "${f}" text)
  string(APPEND body "  {\"${name}\", R\"NESSHI(${text})NESSHI\"},\n")
endforeach()
string(APPEND body "};\n}\n")
file(WRITE "${OUT}.tmp" "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
