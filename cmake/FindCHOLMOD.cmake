# SPDX-License-Identifier: MIT
# FindCHOLMOD: SuiteSparse's CHOLMOD where no CMake package is installed (Debian/Ubuntu
# libsuitesparse-dev 5.x). Honours CHOLMOD_ROOT.
#
#   CHOLMOD_USE_STATIC_LIBS  link libcholmod.a and its SuiteSparse companions (default OFF)
#
# Defines CHOLMOD_FOUND, CHOLMOD_VERSION, CHOLMOD_INCLUDE_DIRS, CHOLMOD_LIBRARIES and the imported
# target CHOLMOD::CHOLMOD.
#
# A shared libcholmod records its own dependencies; they are linked explicitly anyway so strict
# linkers (--no-undefined, --as-needed orders) work. A static libcholmod.a needs all of them in
# order: AMD, CAMD, COLAMD, CCOLAMD, METIS (Debian builds CHOLMOD with its Partition module),
# SuiteSparse_config, LAPACK, BLAS, the OpenMP runtime and libm. BLAS/LAPACK are the generic
# libblas/liblapack, so Debian's alternatives pick the implementation (OpenBLAS when installed).

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)

set(_cholmod_saved_suffixes "${CMAKE_FIND_LIBRARY_SUFFIXES}")
if(CHOLMOD_USE_STATIC_LIBS)
  set(CMAKE_FIND_LIBRARY_SUFFIXES .a)
endif()
find_library(CHOLMOD_LIBRARY cholmod)
foreach(dep amd camd colamd ccolamd suitesparseconfig)
  string(TOUPPER ${dep} _DEP)
  find_library(CHOLMOD_${_DEP}_LIBRARY ${dep})
endforeach()
set(CMAKE_FIND_LIBRARY_SUFFIXES "${_cholmod_saved_suffixes}")
# Debian ships METIS's runtime (libmetis5) with CHOLMOD but the link name only with libmetis-dev.
find_library(CHOLMOD_METIS_LIBRARY NAMES metis libmetis.so.5)
find_library(CHOLMOD_LAPACK_LIBRARY NAMES lapack liblapack.so.3)
find_library(CHOLMOD_BLAS_LIBRARY NAMES blas libblas.so.3)

# The version lives in cholmod.h (SuiteSparse ≥ 6) or in cholmod_core.h (5.x, included by cholmod.h).
if(CHOLMOD_INCLUDE_DIR)
  foreach(_header cholmod.h cholmod_core.h)
    if(NOT CHOLMOD_VERSION AND EXISTS "${CHOLMOD_INCLUDE_DIR}/${_header}")
      file(STRINGS "${CHOLMOD_INCLUDE_DIR}/${_header}" _cholmod_version_lines
           REGEX "^#define[ \t]+CHOLMOD_(MAIN|SUB|SUBSUB)_VERSION[ \t]+[0-9]+")
      if(_cholmod_version_lines)
        foreach(_part MAIN SUB SUBSUB)
          string(REGEX REPLACE ".*#define[ \t]+CHOLMOD_${_part}_VERSION[ \t]+([0-9]+).*" "\\1"
                 _cholmod_${_part} "${_cholmod_version_lines}")
        endforeach()
        set(CHOLMOD_VERSION "${_cholmod_MAIN}.${_cholmod_SUB}.${_cholmod_SUBSUB}")
      endif()
    endif()
  endforeach()
endif()

set(_cholmod_required CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR)
if(CHOLMOD_USE_STATIC_LIBS)
  list(APPEND _cholmod_required CHOLMOD_AMD_LIBRARY CHOLMOD_CAMD_LIBRARY CHOLMOD_COLAMD_LIBRARY
       CHOLMOD_CCOLAMD_LIBRARY CHOLMOD_SUITESPARSECONFIG_LIBRARY CHOLMOD_METIS_LIBRARY
       CHOLMOD_LAPACK_LIBRARY CHOLMOD_BLAS_LIBRARY)
  set(_cholmod_openmp_langs "")
  get_property(_cholmod_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  foreach(_lang C CXX)
    if(_lang IN_LIST _cholmod_languages)
      list(APPEND _cholmod_openmp_langs ${_lang})
    endif()
  endforeach()
  find_package(OpenMP QUIET COMPONENTS ${_cholmod_openmp_langs})
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD
  REQUIRED_VARS ${_cholmod_required}
  VERSION_VAR CHOLMOD_VERSION)

if(CHOLMOD_FOUND)
  # Link order matters for static archives: users before providers.
  set(_cholmod_deps "")
  foreach(_dep AMD CAMD COLAMD CCOLAMD METIS SUITESPARSECONFIG LAPACK BLAS)
    if(CHOLMOD_${_dep}_LIBRARY)
      list(APPEND _cholmod_deps "${CHOLMOD_${_dep}_LIBRARY}")
    endif()
  endforeach()
  if(CHOLMOD_USE_STATIC_LIBS)
    # Only the runtime library: OpenMP::OpenMP_CXX would add -fopenmp to every consumer.
    if(OpenMP_CXX_LIBRARIES)
      list(APPEND _cholmod_deps ${OpenMP_CXX_LIBRARIES})
    elseif(OpenMP_C_LIBRARIES)
      list(APPEND _cholmod_deps ${OpenMP_C_LIBRARIES})
    endif()
    list(APPEND _cholmod_deps m)
  endif()
  set(CHOLMOD_INCLUDE_DIRS "${CHOLMOD_INCLUDE_DIR}")
  set(CHOLMOD_LIBRARIES "${CHOLMOD_LIBRARY}" ${_cholmod_deps})
  if(NOT TARGET CHOLMOD::CHOLMOD)
    add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
    set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
      IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${_cholmod_deps}")
  endif()
endif()

mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY CHOLMOD_AMD_LIBRARY CHOLMOD_CAMD_LIBRARY
                 CHOLMOD_COLAMD_LIBRARY CHOLMOD_CCOLAMD_LIBRARY CHOLMOD_SUITESPARSECONFIG_LIBRARY
                 CHOLMOD_METIS_LIBRARY CHOLMOD_LAPACK_LIBRARY CHOLMOD_BLAS_LIBRARY)
