# nesshi_add_golden(NAME EXPECTED <file> [WORKDIR <dir>] COMMAND <cmd> [args...])
# Registers a CTest test that runs COMMAND, captures stdout+stderr and the exit status,
# and compares them exactly with EXPECTED. Set NESSHI_UPDATE_GOLDEN=1 to rewrite the file.
function(nesshi_add_golden name)
  cmake_parse_arguments(G "" "EXPECTED;WORKDIR" "COMMAND;LABELS" ${ARGN})
  if(NOT G_WORKDIR)
    set(G_WORKDIR "${CMAKE_SOURCE_DIR}")
  endif()
  add_test(NAME ${name}
           COMMAND bash "${CMAKE_SOURCE_DIR}/tests/cli/golden.sh" "${G_EXPECTED}" ${G_COMMAND}
           WORKING_DIRECTORY "${G_WORKDIR}")
  set(labels golden ${G_LABELS})
  set_tests_properties(${name} PROPERTIES LABELS "${labels}")
endfunction()
