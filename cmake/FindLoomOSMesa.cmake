# OSMesa (Mesa's off-screen renderer, llvmpipe) from Debian's libosmesa6-dev,
# and the Khronos core-profile header GL/glcorearb.h (libgl-dev). Defines
# OSMesa::OSMesa. Loom never links libGL: every GL entry point is resolved
# through OSMesaGetProcAddress, so a process may also link GLFW (the editor).
find_path(LoomOSMesa_INCLUDE_DIR GL/osmesa.h)
find_path(LoomOSMesa_GLCOREARB_DIR GL/glcorearb.h)
find_library(LoomOSMesa_LIBRARY OSMesa)
if(LoomOSMesa_INCLUDE_DIR AND LoomOSMesa_GLCOREARB_DIR AND LoomOSMesa_LIBRARY)
  set(LoomOSMesa_FOUND TRUE)
  if(NOT TARGET OSMesa::OSMesa)
    add_library(OSMesa::OSMesa SHARED IMPORTED)
    set_target_properties(OSMesa::OSMesa PROPERTIES
      IMPORTED_LOCATION "${LoomOSMesa_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${LoomOSMesa_INCLUDE_DIR};${LoomOSMesa_GLCOREARB_DIR}")
  endif()
else()
  set(LoomOSMesa_FOUND FALSE)
  if(LoomOSMesa_FIND_REQUIRED)
    message(FATAL_ERROR "OSMesa not found: install libosmesa6-dev and libgl-dev (scripts/install-deps)")
  endif()
endif()
