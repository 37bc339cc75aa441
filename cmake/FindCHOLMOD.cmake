# SPDX-License-Identifier: MIT
# FindCHOLMOD: SuiteSparse's CHOLMOD for Debian/Ubuntu packages (libsuitesparse-dev 5.x ships no
# CMake config). Defines CHOLMOD_FOUND, CHOLMOD_VERSION and the imported target CHOLMOD::CHOLMOD.
# The shared library carries its own dependencies (AMD, COLAMD, METIS, BLAS/LAPACK through the
# system's alternatives, e.g. OpenBLAS); the companion libraries are linked explicitly as well so
# static builds and strict linkers work.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
foreach(dep amd camd colamd ccolamd suitesparseconfig)
  string(TOUPPER ${dep} DEP)
  find_library(CHOLMOD_${DEP}_LIBRARY ${dep})
endforeach()

if(CHOLMOD_INCLUDE_DIR AND EXISTS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h")
  file(STRINGS "${CHOLMOD_INCLUDE_DIR}/cholmod_core.h" _cholmod_version_lines
       REGEX "#define CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION[ \t]+[0-9]+")
  foreach(part MAIN SUB SUBSUB)
    string(REGEX REPLACE ".*#define CHOLMOD_${part}_VERSION[ \t]+([0-9]+).*" "\\1" _v_${part} "${_cholmod_version_lines}")
  endforeach()
  set(CHOLMOD_VERSION "${_v_MAIN}.${_v_SUB}.${_v_SUBSUB}")
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR CHOLMOD_AMD_LIBRARY CHOLMOD_COLAMD_LIBRARY
                CHOLMOD_SUITESPARSECONFIG_LIBRARY
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set(_cholmod_deps "")
  foreach(dep AMD CAMD COLAMD CCOLAMD SUITESPARSECONFIG)
    if(CHOLMOD_${dep}_LIBRARY)
      list(APPEND _cholmod_deps "${CHOLMOD_${dep}_LIBRARY}")
    endif()
  endforeach()
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${_cholmod_deps}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY)
