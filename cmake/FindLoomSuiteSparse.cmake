# CHOLMOD and UMFPACK from Debian's libsuitesparse-dev (no CMake config there).
# Defines SuiteSparse::cholmod and SuiteSparse::umfpack.
find_path(LoomSuiteSparse_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
set(LoomSuiteSparse_FOUND TRUE)
foreach(lib cholmod umfpack)
  find_library(LoomSuiteSparse_${lib}_LIBRARY ${lib})
  if(NOT LoomSuiteSparse_${lib}_LIBRARY OR NOT LoomSuiteSparse_INCLUDE_DIR)
    set(LoomSuiteSparse_FOUND FALSE)
  elseif(NOT TARGET SuiteSparse::${lib})
    add_library(SuiteSparse::${lib} SHARED IMPORTED)
    set_target_properties(SuiteSparse::${lib} PROPERTIES
      IMPORTED_LOCATION "${LoomSuiteSparse_${lib}_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${LoomSuiteSparse_INCLUDE_DIR}")
  endif()
endforeach()
if(NOT LoomSuiteSparse_FOUND AND LoomSuiteSparse_FIND_REQUIRED)
  message(FATAL_ERROR "CHOLMOD/UMFPACK not found: install libsuitesparse-dev")
endif()
