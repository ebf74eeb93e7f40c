# Build time: precompiled headers for the GoogleTest executables (losmimo_add_test calls
# losmimo_precompile_headers, so a test target added later gets them too).
#
# A test source spends a third of its compile time parsing the same dependency headers:
# GoogleTest and GoogleMock, Eigen, and with the higher layers ceres/ceres.h (in fusion's public
# headers) and MRPT's filter templates. A test target's precompiled header holds the ones its link
# closure brings in; each of its sources then loads them instead of parsing them (measured: 33%
# less CPU per test source, docs/reliability.md, Build time). The libraries and apps are compiled
# without: there code generation at -O3 dominates, a precompiled header saved 11% per source and
# costs 4-13 s per target to build, about as much as it saves on the apps' build (README line 1);
# their objects stay exactly as they were.
#
#   -DLOSMIMO_PCH=OFF   plain builds. Default: ON, except under the sanitizers and with a ccache
#                       compiler launcher, which cannot cache a source that uses a precompiled
#                       header unless its sloppiness allows pch_defines,time_macros (a rebuild
#                       from ccache is faster than one with precompiled headers).
# Sources with their own compile options or definitions (a test's -D) are compiled without it,
# exactly as before.

# Under ASan (-DLOSMIMO_SANITIZE=..., scripts/sanitize) the instrumentation dominates a test
# source's compile time: the same six test sources took 70.9 s of CPU with and 68.7 s without.
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache" OR LOSMIMO_SANITIZE)
  set(losmimo_pch_default OFF)
else()
  set(losmimo_pch_default ON)
endif()
option(LOSMIMO_PCH "Precompiled dependency headers for the losmimo targets" ${losmimo_pch_default})

# Headers every target's sources include (standard library: no header with a static initializer
# such as <iostream>, so that no object gains one).
set(LOSMIMO_PCH_STD <algorithm> <array> <cmath> <cstddef> <cstdint> <functional> <limits> <map>
    <memory> <optional> <ostream> <set> <sstream> <stdexcept> <string> <utility> <vector>)
# Per dependency of the link closure: the headers to precompile.
set(LOSMIMO_PCH_Eigen3::Eigen <Eigen/Dense>)
set(LOSMIMO_PCH_mrpt::random <mrpt/random/RandomGenerators.h>)
set(LOSMIMO_PCH_mrpt::bayes <mrpt/bayes/CKalmanFilterCapable.h> <mrpt/bayes/CParticleFilter.h>)
set(LOSMIMO_PCH_Ceres::ceres <ceres/ceres.h>)
set(LOSMIMO_PCH_mrpt::obs <mrpt/obs/CSensoryFrame.h> <mrpt/serialization/CArchive.h>)
set(LOSMIMO_PCH_GTest::gmock <gtest/gtest.h> <gmock/gmock.h>)

# Every target `target` links, directly or through others, by name (link-only $<LINK_ONLY:...>
# and other generator expressions are skipped: none of them brings headers).
function(_losmimo_link_closure target out)
  set(seen "")
  set(todo ${target})
  while(todo)
    list(POP_FRONT todo t)
    if(t IN_LIST seen)
      continue()
    endif()
    # Imported targets are visible only in the folder that found them (MRPT's in localization/):
    # the name is kept, and what it links is followed where it is visible.
    list(APPEND seen ${t})
    if(NOT TARGET ${t})
      continue()
    endif()
    get_target_property(aliased ${t} ALIASED_TARGET)
    if(aliased)
      list(APPEND todo ${aliased})
    endif()
    get_target_property(type ${t} TYPE)
    set(libs "")
    if(NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(direct ${t} LINK_LIBRARIES)
      if(direct)
        list(APPEND libs ${direct})
      endif()
    endif()
    get_target_property(iface ${t} INTERFACE_LINK_LIBRARIES)
    if(iface)
      list(APPEND libs ${iface})
    endif()
    foreach(l IN LISTS libs)
      if(NOT l MATCHES "^\\$<")
        list(APPEND todo ${l})
      endif()
    endforeach()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# losmimo_precompile_headers(<target>): the target's sources include its precompiled header.
# Deferred to the end of the target's CMakeLists.txt, so that sources, source properties and
# links added after the helper call are seen.
function(losmimo_precompile_headers target)
  if(LOSMIMO_PCH)
    cmake_language(EVAL CODE "cmake_language(DEFER CALL _losmimo_precompile_headers_now [[${target}]])")
  endif()
endfunction()

function(_losmimo_precompile_headers_now target)
  get_target_property(sources ${target} SOURCES)
  set(plain "")
  foreach(src IN LISTS sources)
    if(NOT src MATCHES "\\.(cpp|cc|cxx)$")
      continue()
    endif()
    get_source_file_property(options ${src} COMPILE_OPTIONS)
    get_source_file_property(definitions ${src} COMPILE_DEFINITIONS)
    if(options OR definitions)
      set_source_files_properties(${src} PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
    else()
      list(APPEND plain ${src})
    endif()
  endforeach()
  list(LENGTH plain count)
  if(count LESS 2)  # one source: nothing to share
    return()
  endif()
  _losmimo_link_closure(${target} closure)
  set(headers ${LOSMIMO_PCH_STD})
  foreach(dep IN LISTS closure)
    if(DEFINED LOSMIMO_PCH_${dep})
      list(APPEND headers ${LOSMIMO_PCH_${dep}})
    endif()
  endforeach()
  list(REMOVE_DUPLICATES headers)
  target_precompile_headers(${target} PRIVATE ${headers})
endfunction()

# Unity builds for the libraries (losmimo_unity_groups): sources that include the same heavy
# headers (Eigen, MRPT's filter templates, Ceres) are compiled as one translation unit, so that
# the headers are parsed, and their inline functions and templates instantiated and optimized,
# once per group instead of once per source. Each library lists its groups explicitly: two
# sources whose file-local names (anonymous namespace, static) collide go to different groups,
# and a source in no group is compiled alone, as before. Sources with their own compile options
# (the placement kernels) are never merged by CMake.
#
#   -DLOSMIMO_UNITY=OFF   every source on its own. Default: ON, except under the sanitizers and
#                         the fuzzing build (their instrumentation dominates: nothing to share)
if(LOSMIMO_SANITIZE OR LOSMIMO_FUZZ)
  set(losmimo_unity_default OFF)
else()
  set(losmimo_unity_default ON)
endif()
option(LOSMIMO_UNITY "Compile each library's listed source groups as single translation units"
       ${losmimo_unity_default})

# losmimo_unity_groups(<target> GROUP <source>... [GROUP <source>...]...): each GROUP's sources
# (paths relative to the calling CMakeLists.txt) form one translation unit of <target>.
function(losmimo_unity_groups target)
  if(NOT LOSMIMO_UNITY)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
  set(index 0)
  foreach(arg IN LISTS ARGN)
    if(arg STREQUAL "GROUP")
      math(EXPR index "${index} + 1")
    elseif(index EQUAL 0)
      message(FATAL_ERROR "losmimo_unity_groups(${target}): '${arg}' before the first GROUP")
    else()
      get_target_property(sources ${target} SOURCES)
      if(NOT arg IN_LIST sources)
        message(FATAL_ERROR "losmimo_unity_groups(${target}): ${arg} is not a source of ${target}")
      endif()
      set_source_files_properties(${arg} TARGET_DIRECTORY ${target} PROPERTIES UNITY_GROUP ${target}_${index})
    endif()
  endforeach()
endfunction()
