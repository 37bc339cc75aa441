# SPDX-License-Identifier: MIT
# `cmake --install BUILD [--prefix DIR]` puts the five libraries, their headers, a CMake package and a
# pkg-config file in place (included from the top-level CMakeLists.txt after the library folders):
#
#   DIR/include/dualgraph/{core,types,solvers,dual_graph,frontend}/*.h   (#include "core/graph.h" with
#                                                                        -I DIR/include/dualgraph)
#   DIR/lib/libdualgraph_{core,types,solvers,dual_graph,frontend}.{a|so.0.1.0}
#   DIR/lib/cmake/dualgraph/  dualgraphConfig.cmake (+ Version, Targets, FindCHOLMOD.cmake)
#   DIR/lib/pkgconfig/dualgraph.pc
#
# find_package(dualgraph 0.1 CONFIG REQUIRED) gives dualgraph::core, ::types, ::solvers, ::dual_graph and
# ::frontend, finding Eigen3, CHOLMOD, yaml-cpp and OpenCV itself. The package and the .pc file are
# relocatable (paths relative to their own location), so --prefix at install time works.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DUALGRAPH_EXPORTED_LIBRARIES core types solvers dual_graph frontend)
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
  # gate_pnp_posterior.h is gate_pnp.cpp's own; block_product_avx2.h compiles only with -mavx2 -mfma.
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/${_name}/"
          DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/dualgraph/${_name}"
          FILES_MATCHING PATTERN "*.h" PATTERN "yaml_fields.h" EXCLUDE PATTERN "localizer_params_node.h" EXCLUDE
          PATTERN "gate_pnp_posterior.h" EXCLUDE PATTERN "block_product_avx2.h" EXCLUDE)
endforeach()

install(TARGETS ${_dualgraph_install_targets}
  EXPORT dualgraphTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}"
  INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/dualgraph")

set(DUALGRAPH_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/dualgraph")
install(EXPORT dualgraphTargets NAMESPACE dualgraph:: DESTINATION "${DUALGRAPH_CMAKE_DIR}")
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
# CHOLMOD has no .pc file on Debian: its libraries by full path (libmetis.so.5 has no link name there).
foreach(_lib ${CHOLMOD_LIBRARIES})
  if(_lib MATCHES "^/")
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
install(FILES "${PROJECT_BINARY_DIR}/dualgraph.pc" DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
