# OpenCV modules without the full libopencv-dev: Debian ships each module as
# its own -dev package, but the CMake package config only with all of them
# (which would pull in VTK and Qt). Finds headers and the listed modules and
# defines OpenCV::<module> imported targets.
#   find_package(LoomOpenCV REQUIRED COMPONENTS core imgproc imgcodecs)
find_path(LoomOpenCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
set(LoomOpenCV_FOUND TRUE)
foreach(module IN LISTS LoomOpenCV_FIND_COMPONENTS)
  find_library(LoomOpenCV_${module}_LIBRARY opencv_${module})
  if(NOT LoomOpenCV_${module}_LIBRARY OR NOT LoomOpenCV_INCLUDE_DIR)
    set(LoomOpenCV_FOUND FALSE)
    if(LoomOpenCV_FIND_REQUIRED)
      message(FATAL_ERROR "OpenCV module ${module} not found: install libopencv-${module}-dev")
    endif()
  elseif(NOT TARGET OpenCV::${module})
    add_library(OpenCV::${module} SHARED IMPORTED)
    set_target_properties(OpenCV::${module} PROPERTIES
      IMPORTED_LOCATION "${LoomOpenCV_${module}_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${LoomOpenCV_INCLUDE_DIR}")
  endif()
endforeach()
