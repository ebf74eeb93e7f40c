# Small helpers shared by every losmimo target: one place for warnings, layout and installation.
#
# Installation is part of the helpers, so that a target added later is installed without edits:
#   losmimo_add_library  installs lib/liblosmimo_<name>.a, exports losmimo::<name> (export set
#                        losmimoTargets, cmake/LosmimoPackage.cmake writes the package) and installs
#                        <name>/include/ (every header below it, subfolders kept) into include/
#   losmimo_add_app      installs the executable into bin/
# Both add the target to `losmimo_dist` (everything installed: what scripts/setup builds by default,
# without the tests and benchmarks).
include(GNUInstallDirs)
include(LosmimoBuildSpeed)

if(NOT TARGET losmimo_dist)
  add_custom_target(losmimo_dist)
endif()

# Warnings as errors on our own code only (dependencies come in as -isystem).
function(losmimo_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror
                                           -Wno-error=deprecated-declarations)
endfunction()

# losmimo_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates losmimo_<name> (alias losmimo::<name>) with headers in <name>/include (the folder of
# the calling CMakeLists.txt), installed and exported as losmimo::<name>. Dependencies of the
# exported targets must be imported targets of a package listed in cmake/LosmimoPackage.cmake
# (a new one stops the configure step there, naming it).
function(losmimo_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(losmimo_${name} ${ARG_SOURCES})
  add_library(losmimo::${name} ALIAS losmimo_${name})
  set_target_properties(losmimo_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(losmimo_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(losmimo_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  losmimo_target_warnings(losmimo_${name})

  install(TARGETS losmimo_${name} EXPORT losmimoTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/include)
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
      FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp" PATTERN "*.inl")
  endif()
  set_property(GLOBAL APPEND PROPERTY LOSMIMO_LIBRARIES losmimo_${name})
  add_dependencies(losmimo_dist losmimo_${name})
endfunction()

# losmimo_add_test(<name> SOURCES ... DEPS ... [LABELS ...])
# One GoogleTest executable; every TEST becomes its own ctest entry. A TEST that calls
# GTEST_SKIP is reported by ctest as skipped, not passed: CMake's gtest_discover_tests gives
# every test SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" (scripts/check-no-skips lists them).
function(losmimo_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest_main GTest::gmock)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  losmimo_target_warnings(${name})
  losmimo_precompile_headers(${name})
  if(LOSMIMO_SANITIZE MATCHES "undefined" AND NOT LOSMIMO_UBSAN_TEST_FILES)
    target_compile_options(${name} PRIVATE -fno-sanitize=undefined)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${ARG_LABELS}")
endfunction()

# losmimo_add_app(<name> SOURCES ... DEPS ...): a thin main over a library entry point, installed
# into bin/. LOSMIMO_VERSION (the project's version, a string) is defined for its --version.
function(losmimo_add_app name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  target_compile_definitions(${name} PRIVATE LOSMIMO_VERSION="${PROJECT_VERSION}")
  # A main only builds its command line (CLI11, header-only) and calls the library: -O1 instead
  # of Release's -O3 compiles it with a third less CPU (losmimo_eval.cpp 10.2 s -> 6.7 s); the
  # work runs in the libraries, at -O3.
  target_compile_options(${name} PRIVATE $<$<CONFIG:Release>:-O1>)
  losmimo_target_warnings(${name})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  add_dependencies(losmimo_dist ${name})
endfunction()
