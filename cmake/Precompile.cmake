# Precompiled headers: the standard library, fmt and nlohmann-json make up most of what each source
# file parses (paper/src/sweep_spec.cpp: 157,000 preprocessed lines, half its compile time spent
# parsing). One target compiles them (nesshi_precompile) and the others whose flags match reuse it
# (nesshi_use_pch): the libraries reuse nesshi_base's, the test suites base_tests' (with Catch2).
# A header compiled with other flags (-fPIC against -fPIE, -fno-math-errno) is refused by the
# compiler, which then parses the headers again: -Winvalid-pch says so, an error in CI (-Werror),
# so a reuse that does not match cannot land.
option(NESSHI_PCH "Precompile the standard, fmt and JSON headers (and Catch2 for the tests) once" ON)

set(NESSHI_PCH_HEADERS <algorithm> <array> <cmath> <cstdint> <filesystem> <functional> <map> <memory>
    <optional> <set> <stdexcept> <string> <string_view> <unordered_map> <utility> <vector>
    <fmt/format.h> <fmt/ranges.h> <nlohmann/json.hpp>)

# The macros the headers are compiled with (FMT_SHARED from fmt::fmt) must be each user's too.
# GCC 12 reports libstdc++'s own string moves as out of bounds (-Warray-bounds, -Wstringop-overread,
# -Wstringop-overflow: its middle-end warnings, e.g. on a push_back of a braced struct holding a
# string) in some files when the headers come precompiled, never without them: false positives.
# Out-of-bounds accesses are the sanitizers' job (make test-asan, part of CI). GCC 12 only.
function(nesshi_pch_links target)
  target_link_libraries(${target} PRIVATE fmt::fmt nlohmann_json::nlohmann_json)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-array-bounds -Wno-stringop-overread -Wno-stringop-overflow)
  endif()
endfunction()

# nesshi_precompile(<target> [<extra header>...]): the target compiles the common headers once.
function(nesshi_precompile target)
  if(NESSHI_PCH)
    nesshi_pch_links(${target})
    target_precompile_headers(${target} PRIVATE ${NESSHI_PCH_HEADERS} ${ARGN})
  endif()
endfunction()

# nesshi_use_pch(<owner> <target>...): each target reuses the owner's precompiled headers.
function(nesshi_use_pch owner)
  if(NESSHI_PCH)
    foreach(t ${ARGN})
      nesshi_pch_links(${t})
      target_precompile_headers(${t} REUSE_FROM ${owner})
    endforeach()
  endif()
endfunction()
