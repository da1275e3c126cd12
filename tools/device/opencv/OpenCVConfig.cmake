# find_package(OpenCV) on the GPU machine, which has no OpenCV: Debian's
# headers and the modules the ROS-free cores use (core, imgproc, features2d,
# calib3d, flann, video with its dependency dnn), with the libraries they load, packed by
# `tools/device/prepare.sh opencv` and unpacked by the device scripts into
# HAPI_DEVICE_OPENCV (include/opencv4, lib). Image codecs (imgcodecs) are not
# carried: they pull in ~130 libraries (GDAL, codecs); the cores read no
# image files there (hapi_sim renders the generated globe texture).
# Pass -DOpenCV_DIR=<repo>/tools/device/opencv -DHAPI_DEVICE_OPENCV=<dir>.
set(_hapi_cv_modules core imgproc features2d calib3d flann video dnn)
if(NOT HAPI_DEVICE_OPENCV OR NOT EXISTS "${HAPI_DEVICE_OPENCV}/include/opencv4/opencv2/core.hpp")
  set(OpenCV_FOUND FALSE)
  if(OpenCV_FIND_REQUIRED)
    message(FATAL_ERROR "HAPI_DEVICE_OPENCV does not hold the carried OpenCV (tools/device/prepare.sh opencv)")
  endif()
  return()
endif()
set(OpenCV_VERSION 4.6.0)
set(OpenCV_INCLUDE_DIRS "${HAPI_DEVICE_OPENCV}/include/opencv4")
foreach(_m IN LISTS _hapi_cv_modules)
  if(NOT TARGET opencv_${_m})
    add_library(opencv_${_m} SHARED IMPORTED)
    set_target_properties(opencv_${_m} PROPERTIES
      IMPORTED_LOCATION "${HAPI_DEVICE_OPENCV}/lib/libopencv_${_m}.so.406"
      INTERFACE_INCLUDE_DIRECTORIES "${OpenCV_INCLUDE_DIRS}"
      # The linker resolves the modules' own dependencies in the same folder.
      INTERFACE_LINK_OPTIONS "-Wl,-rpath-link,${HAPI_DEVICE_OPENCV}/lib")
  endif()
endforeach()
set(OpenCV_FOUND TRUE)
set(OpenCV_LIBS)
foreach(_c IN LISTS OpenCV_FIND_COMPONENTS)
  if(NOT _c IN_LIST _hapi_cv_modules)
    set(OpenCV_FOUND FALSE)
    if(OpenCV_FIND_REQUIRED)
      message(FATAL_ERROR "OpenCV module ${_c} is not carried to the GPU machine")
    endif()
  endif()
  list(APPEND OpenCV_LIBS opencv_${_c})
endforeach()
set(OpenCV_LIBRARIES ${OpenCV_LIBS})
