# ctest Install.Downstream: installs the build into a scratch prefix, then configures, builds and
# runs tests/downstream against it with find_package(losmimo), and runs an installed app.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DGENERATOR=Ninja]
#         [-DCXX_COMPILER=...] [-DCXX_LAUNCHER=ccache] [-DCXX_FLAGS=...] -P check.cmake
# (CXX_FLAGS: the build's sanitizer flags, which the installed libraries need downstream too.)
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "check.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  string(REPLACE ";" " " cmd "${ARGN}")
  message("$ ${cmd}\n${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "FAILED (exit ${rc}): ${cmd}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(f lib/cmake/losmimo/losmimoConfig.cmake lib/cmake/losmimo/losmimoConfigVersion.cmake
          include/losmimo/placement/gd.h share/losmimo/configs/paper.ini
          share/losmimo/examples/ura_optimal_16.csv
          bin/losmimo-experiment bin/losmimo-eval bin/losmimo-record bin/losmimo-replay)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()

set(args -S ${SOURCE_DIR}/tests/downstream -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${prefix}
         -DCMAKE_BUILD_TYPE=Release)
if(GENERATOR)
  list(APPEND args -G ${GENERATOR})
endif()
if(CXX_COMPILER)
  list(APPEND args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(CXX_LAUNCHER)
  list(APPEND args -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER})
endif()
if(CXX_FLAGS)
  list(APPEND args "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CXX_FLAGS}")
endif()
run(${CMAKE_COMMAND} ${args})
if(NOT last_output MATCHES "from ${prefix}/lib/cmake/losmimo")
  message(FATAL_ERROR "find_package(losmimo) did not take the package from ${prefix}")
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/place_and_evaluate ${prefix}/share/losmimo/configs/paper.ini)
if(NOT last_output MATCHES "status converged" OR NOT last_output MATCHES "icn start [0-9.e-]+ final 0\\.9[5-9]")
  message(FATAL_ERROR "place_and_evaluate: expected a converged GD run ending at ICN >= 0.95")
endif()

# The installed apps run from the prefix, with the installed data.
run(${prefix}/bin/losmimo-eval --positions ${prefix}/share/losmimo/examples/ura_optimal_16.csv)
run(${prefix}/bin/losmimo-eval --version)
if(NOT last_output MATCHES "^losmimo [0-9]+\\.[0-9]+\\.[0-9]+ \\((sse2|avx2|avx512) kernels\\)\n$")
  message(FATAL_ERROR "losmimo-eval --version: unexpected '${last_output}'")
endif()
message("Install.Downstream: PASS")
