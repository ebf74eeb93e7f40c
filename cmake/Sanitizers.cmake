# Sanitizer and fuzzing builds. Included by the top-level CMakeLists before any
# add_subdirectory, so the flags reach every losmimo target: libraries, apps, tests, benchmarks.
# (Directory-scoped add_compile_options / add_link_options, not CMAKE_CXX_FLAGS edits.)
#
#   -DLOSMIMO_SANITIZE=address,undefined   ASan + UBSan on everything (scripts/sanitize); the
#                                          test files ASan only (LOSMIMO_UBSAN_TEST_FILES)
#   -DLOSMIMO_FUZZ=ON                      clang only: libFuzzer targets in tests/fuzz, and
#                                          everything instrumented for coverage + ASan + UBSan
#                                          (scripts/fuzz-smoke)
# Any UBSan finding aborts (-fno-sanitize-recover=all): a report is a failure, never a warning.

set(LOSMIMO_SANITIZE "" CACHE STRING
    "Comma-separated sanitizers for every losmimo target, e.g. address,undefined (empty: none)")
option(LOSMIMO_FUZZ "Build the libFuzzer targets in tests/fuzz (clang only)" OFF)
# UBSan's checks double the compile time of a test file at -O1 (32 s -> 15 s for
# channel_metrics_test.cpp without them) while the code under test is in the libraries, which
# keep them: test files get ASan only unless this is ON (losmimo_add_test).
option(LOSMIMO_UBSAN_TEST_FILES "With LOSMIMO_SANITIZE=...undefined: instrument the test files too" OFF)

if(LOSMIMO_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "LOSMIMO_FUZZ=ON needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++; "
                        "the compiler is ${CMAKE_CXX_COMPILER_ID}")
  endif()
  if(NOT LOSMIMO_SANITIZE)
    set(LOSMIMO_SANITIZE "address,undefined" CACHE STRING
        "Comma-separated sanitizers for every losmimo target" FORCE)
  endif()
  # Coverage instrumentation for the libraries; the fuzz executables add -fsanitize=fuzzer
  # (which brings libFuzzer's main) themselves.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(LOSMIMO_SANITIZE)
  message(STATUS "losmimo: sanitizers ${LOSMIMO_SANITIZE}")
  add_compile_options(-fsanitize=${LOSMIMO_SANITIZE} -fno-omit-frame-pointer
                      -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${LOSMIMO_SANITIZE})
  # Debian's libceres.a is built without ASan, so its copies of Eigen templates (e.g.
  # JacobiSVD<MatrixXcd>) allocate with plain malloc, while under ASan Eigen would switch our
  # copies to its hand-made aligned allocator; the linker keeps one copy of each, and a buffer
  # allocated by one and freed by the other is a heap overflow. ASan's malloc is 16-byte aligned
  # on x86-64 as glibc's is, so every copy uses malloc.
  add_compile_definitions(EIGEN_MALLOC_ALREADY_ALIGNED=1)
  # GCC 12 + ASan: false -Wmaybe-uninitialized in <regex> / <functional> (std::function in
  # regex_automaton.h); keep it a warning so -Werror does not stop the sanitizer build.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-error=maybe-uninitialized)
  endif()
endif()
