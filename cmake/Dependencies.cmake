# Finds the Debian packages spectralize builds with, working around two packaging bugs of
# Debian 12 (see docs/DESIGN.md §11).

find_package(fmt REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
find_package(OpenImageIO REQUIRED)
find_package(Imath REQUIRED)
find_package(OpenEXR REQUIRED)

# OIIO's exported target names /usr/include/opencv4, which does not exist without OpenCV's
# headers; CMake refuses non-existent include dirs on imported targets.
get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
if(_oiio_inc)
  list(FILTER _oiio_inc EXCLUDE REGEX "opencv4")
  set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_inc}")
endif()
foreach(_t OpenImageIO::OpenImageIO_Util)
  if(TARGET ${_t})
    get_target_property(_inc ${_t} INTERFACE_INCLUDE_DIRECTORIES)
    if(_inc)
      list(FILTER _inc EXCLUDE REGEX "opencv4")
      set_target_properties(${_t} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_inc}")
    endif()
  endif()
endforeach()

# OpenColorIO's own CMake package first. Debian 12 installs it in /usr/share/cmake, where
# find_package does not look and where its computed prefix would be wrong; a package whose
# library is not where it says is not used either. Then the imported target is built by hand.
find_package(OpenColorIO CONFIG QUIET)
if(TARGET OpenColorIO::OpenColorIO)
  get_target_property(_ocio_lib OpenColorIO::OpenColorIO IMPORTED_LOCATION_RELEASE)
  if(NOT _ocio_lib)
    get_target_property(_ocio_lib OpenColorIO::OpenColorIO IMPORTED_LOCATION)
  endif()
  if(_ocio_lib AND EXISTS "${_ocio_lib}")
    message(STATUS "OpenColorIO: its CMake package (${_ocio_lib})")
    set(_ocio_from_package ON)
  endif()
endif()
if(NOT _ocio_from_package)
  find_path(OCIO_INCLUDE_DIR OpenColorIO/OpenColorIO.h REQUIRED)
  find_library(OCIO_LIBRARY NAMES OpenColorIO REQUIRED)
  if(NOT TARGET OpenColorIO::OpenColorIO)
    add_library(OpenColorIO::OpenColorIO UNKNOWN IMPORTED)
  endif()
  set_target_properties(OpenColorIO::OpenColorIO PROPERTIES
    IMPORTED_LOCATION "${OCIO_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OCIO_INCLUDE_DIR}")
endif()

# LittleCMS makes the ICC profiles of TIFF, PNG and JPEG outputs (colour/icc_profile.cpp only).
find_package(PkgConfig REQUIRED)
pkg_check_modules(LCMS2 REQUIRED IMPORTED_TARGET lcms2)

find_program(OCIOCHECK_EXECUTABLE ociocheck)

# The Python module is built for the interpreter Debian's python3-numpy, pybind11 and
# OpenImageIO bindings belong to (/usr/bin/python3), not for one earlier in PATH (pyenv,
# conda); -DPython3_EXECUTABLE=... chooses another.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG QUIET)
