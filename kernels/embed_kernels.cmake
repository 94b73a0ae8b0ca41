# Writes kernel_sources.cpp: each kernel (kernels/*/*.s), its source before scheduling
# (kernels/*/*.pk) and abi.inc as a string, so an installed `nesshi` needs no source tree (run at
# build time whenever a source changes).
file(GLOB files RELATIVE "${SRC_DIR}" "${SRC_DIR}/abi.inc" "${SRC_DIR}/*/*.s" "${SRC_DIR}/*/*.pk")
list(SORT files)
set(body "// Generated from kernels/ by embed_kernels.cmake; do not edit.\n#include \"kernels/sources.hpp\"\nnamespace nesshi::kernels {\nconst std::vector<SourceFile>& embedded_sources() {\n  static const std::vector<SourceFile> files = {\n")
foreach(f ${files})
  file(READ "${SRC_DIR}/${f}" text)
  string(APPEND body "    {\"${f}\", R\"NESSHI(${text})NESSHI\"},\n")
endforeach()
string(APPEND body "  };\n  return files;\n}\n}\n")
file(WRITE "${OUT}.tmp" "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
