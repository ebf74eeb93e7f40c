# Installation and packaging, included by the top-level CMakeLists after every target exists.
#   cmake --install build --prefix P   libraries (lib/), headers (include/losmimo/...), the apps
#                                      (bin/), the shipped configs and example positions
#                                      (share/losmimo/), the CMake package (lib/cmake/losmimo/)
#   cpack -G DEB (scripts/package-deb) the same under /usr as build/losmimo_<version>_amd64.deb
# The libraries and apps install themselves (cmake/LosmimoHelpers.cmake); this file writes the
# package files around the export set losmimoTargets.
include(CMakePackageConfigHelpers)

set(LOSMIMO_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/losmimo)
set(LOSMIMO_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/losmimo)

# find_dependency() lines for losmimoConfig.cmake, from the link interfaces of the exported
# libraries: one line per package, e.g. mrpt::bayes and mrpt::obs -> MRPT COMPONENTS bayes obs.
# The packages' find arguments (minimum versions as the project requires them); a namespace not
# listed here stops the configure step, so a new dependency cannot leave the package broken.
set(losmimo_package_of_Eigen3 "Eigen3 3.4 NO_MODULE")
set(losmimo_package_of_Threads "Threads")
set(losmimo_package_of_mrpt "MRPT 2.5")  # + COMPONENTS, the mrpt:: targets used
set(losmimo_package_of_Ceres "Ceres 2.1")
set(losmimo_package_of_ZLIB "ZLIB")

function(losmimo_find_dependency_lines out_var)
  get_property(libraries GLOBAL PROPERTY LOSMIMO_LIBRARIES)
  set(namespaces "")
  set(mrpt_components "")
  foreach(lib IN LISTS libraries)
    get_target_property(deps ${lib} INTERFACE_LINK_LIBRARIES)
    if(NOT deps)
      continue()
    endif()
    foreach(dep IN LISTS deps)
      # Plain names, and $<LINK_ONLY:...> (private dependencies of a static library).
      # Plain names (m, dl) are the linker's to find, on any machine.
      string(REGEX MATCHALL "[A-Za-z0-9_.+-]+::[A-Za-z0-9_.+-]+" names "${dep}")
      foreach(name IN LISTS names)
        string(REGEX REPLACE "::.*" "" ns "${name}")
        string(REGEX REPLACE ".*::" "" component "${name}")
        if(ns STREQUAL "losmimo")
          continue()
        endif()
        if(NOT DEFINED losmimo_package_of_${ns})
          message(FATAL_ERROR "losmimo: ${lib} links ${name}: add its package to "
                              "cmake/LosmimoPackage.cmake (losmimo_package_of_${ns}) so that "
                              "losmimoConfig.cmake finds it")
        endif()
        list(APPEND namespaces ${ns})
        if(ns STREQUAL "mrpt")
          list(APPEND mrpt_components ${component})
        endif()
      endforeach()
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES namespaces)
  list(REMOVE_DUPLICATES mrpt_components)
  # Threads and Eigen first (the others' configs use them), then by name.
  list(SORT namespaces)
  set(lines "")
  set(order Threads Eigen3 ${namespaces})
  list(REMOVE_DUPLICATES order)
  foreach(ns IN LISTS order)
    if(NOT ns IN_LIST namespaces)
      continue()
    endif()
    set(args "${losmimo_package_of_${ns}}")
    if(ns STREQUAL "mrpt")
      list(JOIN mrpt_components " " comps)
      string(APPEND args " COMPONENTS ${comps}")
    endif()
    string(APPEND lines "find_dependency(${args})\n")
  endforeach()
  set(${out_var} "${lines}" PARENT_SCOPE)
endfunction()

losmimo_find_dependency_lines(LOSMIMO_FIND_DEPENDENCIES)
string(REGEX REPLACE "find_dependency\\(([^)]*)\\)\n" "\\1; " losmimo_found_summary "${LOSMIMO_FIND_DEPENDENCIES}")
message(STATUS "losmimo: losmimoConfig.cmake finds ${losmimo_found_summary}")

install(EXPORT losmimoTargets NAMESPACE losmimo:: FILE losmimoTargets.cmake
        DESTINATION ${LOSMIMO_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/losmimoConfig.cmake.in
  ${PROJECT_BINARY_DIR}/losmimoConfig.cmake
  INSTALL_DESTINATION ${LOSMIMO_INSTALL_CMAKEDIR}
  PATH_VARS LOSMIMO_INSTALL_DATADIR)
# 0.x: a minor version may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/losmimoConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/losmimoConfig.cmake ${PROJECT_BINARY_DIR}/losmimoConfigVersion.cmake
        DESTINATION ${LOSMIMO_INSTALL_CMAKEDIR})

# The shipped configurations and example positions: share/losmimo/{configs,examples}.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/datasets/configs/ DESTINATION ${LOSMIMO_INSTALL_DATADIR}/configs
        FILES_MATCHING PATTERN "*.ini")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/datasets/examples/ DESTINATION ${LOSMIMO_INSTALL_DATADIR}/examples
        FILES_MATCHING PATTERN "*.csv")

# Debian package (cpack -G DEB in the build folder; scripts/package-deb builds and checks it).
set(CPACK_PACKAGE_NAME losmimo)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "losmimo")
set(LOSMIMO_DEB_MAINTAINER "losmimo maintainers <losmimo@example.org>" CACHE STRING
    "The Debian package's Maintainer field")
set(CPACK_PACKAGE_CONTACT "${LOSMIMO_DEB_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "UAV swarm placement for line-of-sight MIMO backhaul, with MRPT localization")
set(CPACK_PACKAGE_DESCRIPTION
    "Moves a swarm of UAVs into the positions that give the highest-capacity line-of-sight MIMO
backhaul from a base station while each UAV estimates where it is: the apps
losmimo-experiment, losmimo-eval, losmimo-record and losmimo-replay, the shipped
configurations in /usr/share/losmimo, and the C++ libraries (static) with their
headers and CMake package (find_package(losmimo)).")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # losmimo_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CPACK_PACKAGE_CONTACT}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# The shared libraries the apps link (MRPT, and libceres.a's own: glog, SuiteSparse, BLAS, ...):
# from dpkg-shlibdeps. gnuplot draws the experiment's figures (without it they are skipped, with
# a warning). The -dev packages are what find_package(losmimo) needs to build against the
# libraries.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "gnuplot-nox")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libeigen3-dev, libceres-dev, libmrpt-bayes-dev, libmrpt-obs-dev, libmrpt-opengl-dev, zlib1g-dev")
include(CPack)
