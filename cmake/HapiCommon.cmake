# Settings shared by every HAPI package, in catkin and in plain-CMake builds.
include_guard(GLOBAL)
# Included once, from the repository root, before any package is added.

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
set(CMAKE_CXX_STANDARD 17)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

# CUDA is optional: every feature has a CPU path, and machines without nvcc
# (or with HAPI_WITH_CUDA=OFF) build the CPU path only.
# Targets: Jetson Orin (sm_87) and H100/H200 (sm_90).
option(HAPI_WITH_CUDA "Build the CUDA backends when nvcc is available" ON)
set(HAPI_CUDA_FOUND OFF)
if(HAPI_WITH_CUDA)
  if(NOT CMAKE_CUDA_COMPILER AND EXISTS /usr/local/cuda/bin/nvcc)
    set(CMAKE_CUDA_COMPILER /usr/local/cuda/bin/nvcc)
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES 87 90)
    endif()
    enable_language(CUDA)
    set(CMAKE_CUDA_STANDARD 17)
    set(CMAKE_CUDA_STANDARD_REQUIRED ON)
    find_package(CUDAToolkit REQUIRED)
    set(HAPI_CUDA_FOUND ON)
    message(STATUS "HAPI: CUDA backends enabled (archs ${CMAKE_CUDA_ARCHITECTURES})")
  else()
    message(STATUS "HAPI: nvcc not found, CPU path only")
  endif()
endif()

find_package(Eigen3 REQUIRED NO_MODULE)

# gtest for the ROS-free build (catkin brings its own via catkin_add_gtest).
# hapi_add_core_gtest(name SOURCES ... LIBS ...) registers a gtest in both worlds.
function(hapi_add_core_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  if(catkin_FOUND AND COMMAND catkin_add_gtest)
    if(CATKIN_ENABLE_TESTING)
      catkin_add_gtest(${name} ${ARG_SOURCES})
      if(TARGET ${name})
        target_link_libraries(${name} ${ARG_LIBS} GTest::gtest_main)
      endif()
    endif()
  else()
    find_package(GTest REQUIRED)
    add_executable(${name} ${ARG_SOURCES})
    target_link_libraries(${name} ${ARG_LIBS} GTest::gtest GTest::gtest_main)
    add_test(NAME ${name} COMMAND ${name})
  endif()
endfunction()
