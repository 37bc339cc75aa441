# SPDX-License-Identifier: MIT
# `cmake --install BUILD [--prefix DIR]` puts the five libraries, their headers, a CMake package and
# pkg-config files in place (included from the top-level CMakeLists.txt after the library folders):
#
#   DIR/include/dualgraph/{core,types,solvers,dual_graph,frontend}/*.h   (#include "dualgraph/core/graph.h"
#                                                                        with -I DIR/include)
#   DIR/lib/libdualgraph_{core,types,solvers,dual_graph,onboard,frontend}.{a|so.0.1.0}
#   DIR/lib/cmake/dualgraph/  dualgraphConfig.cmake (+ Version, one Targets file per component, FindCHOLMOD.cmake)
#   DIR/lib/pkgconfig/dualgraph.pc (everything) and dualgraph-engine.pc (core, types, solvers: Eigen + CHOLMOD)
#
# find_package(dualgraph 0.1 CONFIG REQUIRED [COMPONENTS core types solvers dual_graph onboard frontend]) gives the
# targets dualgraph::<component> of the components asked for and of those they need, finding only their
# dependencies (the engine alone: Eigen, and CHOLMOD for a static build; onboard adds yaml-cpp and OpenCV).
# No COMPONENTS: all six. The package and the .pc files are relocatable (paths relative to their own
# location; the system libraries by name), so --prefix at install time and a moved prefix work.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DUALGRAPH_EXPORTED_LIBRARIES core types solvers dual_graph onboard frontend)
# The header folders of each library (repository paths); the two frontend libraries share frontend/.
set(_dualgraph_headers_core core)
set(_dualgraph_headers_types types)
set(_dualgraph_headers_solvers solvers)
set(_dualgraph_headers_dual_graph dual_graph)
set(_dualgraph_headers_onboard frontend/gates frontend/io frontend/calibration frontend/pipeline)
set(_dualgraph_headers_frontend frontend/simulation frontend/replay frontend/evaluation frontend/report)
set(_dualgraph_install_targets "")
foreach(_name ${DUALGRAPH_EXPORTED_LIBRARIES})
  if(NOT TARGET dualgraph_${_name})
    message(FATAL_ERROR "dualgraph_install: library target dualgraph_${_name} is not defined")
  endif()
  # SOVERSION major.minor: before 1.0 a minor release may break the ABI. PIC so the Python module (a
  # shared object) can link the static libraries.
  set_target_properties(dualgraph_${_name} PROPERTIES
    EXPORT_NAME ${_name}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    POSITION_INDEPENDENT_CODE ON
    INSTALL_RPATH "$ORIGIN")  # shared builds: an installed library finds its siblings (frontend → solvers)
  list(APPEND _dualgraph_install_targets dualgraph_${_name})
  # Headers keep the repository's include layout. The private ones include yaml-cpp or OpenCV, which the
  # package does not promise its users (.ci/install-example fails if an installed header includes them);
  # gate_pnp_posterior.h and gate_pnp_upright.h are gate_pnp.cpp's own; block_product_avx2.h compiles only with
  # -mavx2 -mfma.
  foreach(_folder ${_dualgraph_headers_${_name}})
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/${_folder}/"
            DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/dualgraph/${_folder}"
            FILES_MATCHING PATTERN "*.h" PATTERN "yaml_fields.h" EXCLUDE PATTERN "localizer_params_node.h" EXCLUDE
            PATTERN "gate_pnp_posterior.h" EXCLUDE PATTERN "gate_pnp_upright.h" EXCLUDE
            PATTERN "block_product_avx2.h" EXCLUDE)
  endforeach()
endforeach()

# One export set per component, so that a consumer asking for the engine loads (and finds the dependencies
# of) the engine only; dualgraphConfig.cmake includes the files of the components asked for.
set(DUALGRAPH_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/dualgraph")
foreach(_name ${DUALGRAPH_EXPORTED_LIBRARIES})
  install(TARGETS dualgraph_${_name}
    EXPORT dualgraph_${_name}Targets
    ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
    INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
  install(EXPORT dualgraph_${_name}Targets NAMESPACE dualgraph:: DESTINATION "${DUALGRAPH_CMAKE_DIR}")
endforeach()
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/dualgraphConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/dualgraphConfig.cmake" INSTALL_DESTINATION "${DUALGRAPH_CMAKE_DIR}")
# 0.x: only the same minor version is compatible (see SOVERSION).
write_basic_package_version_file("${PROJECT_BINARY_DIR}/dualgraphConfigVersion.cmake"
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/dualgraphConfig.cmake" "${PROJECT_BINARY_DIR}/dualgraphConfigVersion.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/FindCHOLMOD.cmake"
        DESTINATION "${DUALGRAPH_CMAKE_DIR}")

# pkg-config: prefix relative to the .pc file's folder; static libraries need their dependencies in
# Libs/Requires, shared ones only privately.
file(RELATIVE_PATH DUALGRAPH_PC_PREFIX_FROM_PCDIR "${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig" "${CMAKE_INSTALL_PREFIX}")
string(REGEX REPLACE "/$" "" DUALGRAPH_PC_PREFIX_FROM_PCDIR "${DUALGRAPH_PC_PREFIX_FROM_PCDIR}")
file(RELATIVE_PATH DUALGRAPH_PC_LIBDIR "${CMAKE_INSTALL_PREFIX}" "${CMAKE_INSTALL_FULL_LIBDIR}")
file(RELATIVE_PATH DUALGRAPH_PC_INCLUDEDIR "${CMAKE_INSTALL_PREFIX}" "${CMAKE_INSTALL_FULL_INCLUDEDIR}")
set(_dualgraph_cholmod_libs "")
# CHOLMOD has no .pc file on Debian: its libraries by name, never by this machine's path (the .pc must work
# wherever the prefix and the system libraries are). A library found only under its run-time name
# (libmetis.so.5: Debian ships no link name for it without libmetis-dev) is named as such: -l:libmetis.so.5.
foreach(_lib ${CHOLMOD_LIBRARIES})
  get_filename_component(_file "${_lib}" NAME)
  if(_file MATCHES "^lib(.+)\\.(so|a)$")
    string(APPEND _dualgraph_cholmod_libs " -l${CMAKE_MATCH_1}")
  elseif(_file MATCHES "^lib.+\\.so\\.[0-9.]+$")
    string(APPEND _dualgraph_cholmod_libs " -l:${_file}")
  elseif(_lib MATCHES "^-")
    string(APPEND _dualgraph_cholmod_libs " ${_lib}")
  else()
    string(APPEND _dualgraph_cholmod_libs " -l${_lib}")
  endif()
endforeach()
if(BUILD_SHARED_LIBS)
  set(DUALGRAPH_PC_REQUIRES "eigen3")
  set(DUALGRAPH_PC_REQUIRES_PRIVATE "yaml-cpp opencv4")
  set(DUALGRAPH_PC_LIBS_EXTRA "")
  set(DUALGRAPH_PC_LIBS_PRIVATE "${_dualgraph_cholmod_libs}")
else()
  set(DUALGRAPH_PC_REQUIRES "eigen3 yaml-cpp opencv4")
  set(DUALGRAPH_PC_REQUIRES_PRIVATE "")
  set(DUALGRAPH_PC_LIBS_EXTRA "${_dualgraph_cholmod_libs}")
  set(DUALGRAPH_PC_LIBS_PRIVATE "")
endif()
configure_file("${PROJECT_SOURCE_DIR}/cmake/dualgraph.pc.in" "${PROJECT_BINARY_DIR}/dualgraph.pc" @ONLY)
# The engine alone (core, types, solvers): Eigen, and CHOLMOD for static libraries.
if(BUILD_SHARED_LIBS)
  set(DUALGRAPH_ENGINE_PC_LIBS_EXTRA "")
  set(DUALGRAPH_ENGINE_PC_LIBS_PRIVATE "${_dualgraph_cholmod_libs}")
else()
  set(DUALGRAPH_ENGINE_PC_LIBS_EXTRA "${_dualgraph_cholmod_libs}")
  set(DUALGRAPH_ENGINE_PC_LIBS_PRIVATE "")
endif()
configure_file("${PROJECT_SOURCE_DIR}/cmake/dualgraph-engine.pc.in" "${PROJECT_BINARY_DIR}/dualgraph-engine.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/dualgraph.pc" "${PROJECT_BINARY_DIR}/dualgraph-engine.pc"
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
