# What `cmake --install` puts under the prefix: the `nesshi` tool, each library with its public
# headers (include/nesshisen/<lib>/), a CMake package (find_package(Nesshisen): Nesshisen::<lib>),
# a pkg-config file (nesshisen.pc), and, from cli/ and python/, man pages, completion and the module.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
set(NESSHI_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/Nesshisen")
set(NESSHI_INSTALL_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}/nesshisen")

# nesshi_library_headers(<target> [<include dir>]): the target's public include folder (default
# include/ beside its CMakeLists), seen from the build tree and from an installed prefix.
function(nesshi_library_headers target)
  set(dir "${CMAKE_CURRENT_SOURCE_DIR}/include")
  target_include_directories(${target} PUBLIC "$<BUILD_INTERFACE:${dir}>"
                                              "$<INSTALL_INTERFACE:${NESSHI_INSTALL_INCLUDEDIR}>")
  install(DIRECTORY "${dir}/" DESTINATION "${NESSHI_INSTALL_INCLUDEDIR}" COMPONENT devel)
endfunction()

# nesshi_install_library(<target>): installed and exported as Nesshisen::<name without nesshi_>.
function(nesshi_install_library target)
  string(REGEX REPLACE "^nesshi_" "" short "${target}")
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${short})
  add_library(Nesshisen::${short} ALIAS ${target})
  install(TARGETS ${target} EXPORT NesshisenTargets
          ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT devel
          LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT devel)
endfunction()

# After every library is declared: the package files. The libraries are static, so the config
# finds what they link (fmt, toml++, JSON, libpng, libedit, threads, and MPI when built with it).
function(nesshi_install_package)
  install(EXPORT NesshisenTargets NAMESPACE Nesshisen:: DESTINATION "${NESSHI_INSTALL_CMAKEDIR}" COMPONENT devel)
  set(NESSHI_CONFIG_HAVE_MPI ${NESSHI_HAVE_MPI})
  configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/NesshisenConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/NesshisenConfig.cmake" INSTALL_DESTINATION "${NESSHI_INSTALL_CMAKEDIR}")
  write_basic_package_version_file("${PROJECT_BINARY_DIR}/NesshisenConfigVersion.cmake"
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES "${PROJECT_BINARY_DIR}/NesshisenConfig.cmake" "${PROJECT_BINARY_DIR}/NesshisenConfigVersion.cmake"
          DESTINATION "${NESSHI_INSTALL_CMAKEDIR}" COMPONENT devel)

  # pkg-config: one module, the libraries from the top layer down (static: order matters).
  set(libs "")
  foreach(t ${ARGN})
    if(NOT TARGET ${t})
      continue()
    endif()
    get_target_property(whole ${t} NESSHI_WHOLE_ARCHIVE)
    if(whole) # nothing names its objects: they register themselves (machine/CMakeLists.txt)
      string(APPEND libs " -Wl,--whole-archive -l${t} -Wl,--no-whole-archive")
    else()
      string(APPEND libs " -l${t}")
    endif()
  endforeach()
  # Then what those static libraries link from the system without a pkg-config module of its
  # own here (the scheduler's z3 and Gecode: sched/CMakeLists.txt).
  get_property(dependency_libs GLOBAL PROPERTY NESSHI_PC_DEPENDENCY_LIBS)
  set(NESSHI_PC_LIBS "${libs}${dependency_libs}")
  set(NESSHI_PC_REQUIRES "fmt nlohmann_json tomlplusplus libpng libedit")
  if(NESSHI_HAVE_MPI)
    string(APPEND NESSHI_PC_REQUIRES " ompi-cxx")
  endif()
  # The prefix is found from the file's own place, so `cmake --install --prefix P` needs no reconfigure.
  file(RELATIVE_PATH NESSHI_PC_UP "/r/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/r")
  configure_file("${PROJECT_SOURCE_DIR}/cmake/nesshisen.pc.in" "${PROJECT_BINARY_DIR}/nesshisen.pc" @ONLY)
  install(FILES "${PROJECT_BINARY_DIR}/nesshisen.pc" DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig" COMPONENT devel)

  # `cpack` in the build folder makes a Debian package of the same tree (installed under /usr).
  set(CPACK_GENERATOR DEB)
  set(CPACK_PACKAGE_NAME nesshisen)
  set(CPACK_PACKAGE_VENDOR "Nesshisen")
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Toolchain and simulator for the VLIW processors of a 1993 ray-tracing machine")
  set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
  set(CPACK_DEBIAN_PACKAGE_MAINTAINER "Nesshisen developers")
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
  include(CPack)
endfunction()
