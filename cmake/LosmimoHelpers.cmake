# Small helpers shared by every losmimo target: one place for warnings and layout.

# Warnings as errors on our own code only (dependencies come in as -isystem).
function(losmimo_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror
                                           -Wno-error=deprecated-declarations)
endfunction()

# losmimo_add_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates losmimo_<name> (alias losmimo::<name>) with headers in <name>/include.
function(losmimo_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(losmimo_${name} ${ARG_SOURCES})
  add_library(losmimo::${name} ALIAS losmimo_${name})
  target_include_directories(losmimo_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
  target_link_libraries(losmimo_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  losmimo_target_warnings(losmimo_${name})
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
  if(LOSMIMO_SANITIZE MATCHES "undefined" AND NOT LOSMIMO_UBSAN_TEST_FILES)
    target_compile_options(${name} PRIVATE -fno-sanitize=undefined)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${ARG_LABELS}")
endfunction()

# losmimo_add_app(<name> SOURCES ... DEPS ...): a thin main over a library entry point.
function(losmimo_add_app name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  losmimo_target_warnings(${name})
endfunction()
