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

# Eigen: the system package, or (on the GPU machine, which has CUDA but no
# Debian -dev packages) a header tree given with -DHAPI_EIGEN_INCLUDE_DIR=...
if(HAPI_EIGEN_INCLUDE_DIR)
  add_library(Eigen3::Eigen INTERFACE IMPORTED GLOBAL)
  set_target_properties(Eigen3::Eigen PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${HAPI_EIGEN_INCLUDE_DIR})
else()
  find_package(Eigen3 REQUIRED NO_MODULE)
endif()

# GoogleTest for the plain build: the system package, or a source tree given
# with -DHAPI_GTEST_SOURCE_DIR=... (built here; used on the GPU machine).
if(NOT catkin_FOUND AND HAPI_GTEST_SOURCE_DIR AND NOT TARGET GTest::gtest)
  set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
  set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
  add_subdirectory(${HAPI_GTEST_SOURCE_DIR} ${CMAKE_BINARY_DIR}/_gtest EXCLUDE_FROM_ALL)
  if(NOT TARGET GTest::gtest)
    add_library(GTest::gtest ALIAS gtest)
    add_library(GTest::gtest_main ALIAS gtest_main)
  endif()
endif()

# gtest for the ROS-free build (catkin brings its own via catkin_add_gtest).
# hapi_set_test_label(test label): gives a test its one label. scripts/test.sh
# runs ctest with -j (the machine's cores), and only `sanitizer` tests run
# beside each other there: the fuzz runs and the sanitized gtests work in
# their own build folder with no ROS master, port or shared file. Every other
# test runs alone (RUN_SERIAL), so rostests and the two-host runs keep the
# timing margins they were written for on a 2-core machine.
function(hapi_set_test_label test label)
  set_tests_properties(${test} PROPERTIES LABELS ${label})
  if(NOT label STREQUAL "sanitizer")
    set_tests_properties(${test} PROPERTIES RUN_SERIAL TRUE)
  endif()
endfunction()

# hapi_add_core_gtest(name SOURCES ... LIBS ... [LABEL l]) registers a gtest in
# both worlds, with test/gtest/hapi_gtest_main.cpp as its main(): a binary
# whose every test skipped (no CUDA device, a back end not built) shows as
# skipped in ctest, not passed. LABEL is the ctest label (default unit).
set(HAPI_GTEST_SUPPORT_DIR ${CMAKE_CURRENT_LIST_DIR}/../test/gtest)
function(hapi_add_core_gtest name)
  cmake_parse_arguments(ARG "" "LABEL" "SOURCES;LIBS" ${ARGN})
  if(NOT ARG_LABEL)
    set(ARG_LABEL unit)
  endif()
  set(main ${HAPI_GTEST_SUPPORT_DIR}/hapi_gtest_main.cpp)
  if(catkin_FOUND AND COMMAND catkin_add_gtest)
    if(NOT CATKIN_ENABLE_TESTING)
      return()
    endif()
    catkin_add_gtest(${name} ${ARG_SOURCES} ${main})
    if(NOT TARGET ${name})
      return()
    endif()
    target_link_libraries(${name} ${ARG_LIBS} GTest::gtest)
    set(test_name _ctest_${PROJECT_NAME}_gtest_${name})
  else()
    if(NOT TARGET GTest::gtest)
      find_package(GTest REQUIRED)
    endif()
    add_executable(${name} ${ARG_SOURCES} ${main})
    target_link_libraries(${name} ${ARG_LIBS} GTest::gtest)
    add_test(NAME ${name} COMMAND ${name})
    set(test_name ${name})
  endif()
  target_include_directories(${name} PRIVATE ${HAPI_GTEST_SUPPORT_DIR})
  set_tests_properties(${test_name} PROPERTIES SKIP_REGULAR_EXPRESSION "\\[ HAPI ALL SKIPPED \\]")
  hapi_set_test_label(${test_name} ${ARG_LABEL})
endfunction()

# Every ctest entry carries exactly one label: unit (ROS-free gtests, tests of
# scripts), system (rostests, launch files, the pipeline end to end),
# reliability (two hosts, link outage, fuzzed input to the running nodelet),
# sanitizer (the instrumented build, its gtests and the fuzz smoke runs).
# `scripts/test.sh --quick` runs unit and system; test/ctest_labels_test.py
# fails on an entry without exactly one of them.
# hapi_label_tests(label): at the end of a CMakeLists, gives every test of
# this folder that has no label yet `label`; a rostest among them is
# `system` where `label` is unit.
function(hapi_label_tests label)
  get_property(tests DIRECTORY PROPERTY TESTS)
  foreach(t IN LISTS tests)
    get_test_property(${t} LABELS have)
    if(have)
      continue()
    endif()
    set(l ${label})
    if(l STREQUAL "unit" AND t MATCHES "^_ctest_.*_rostest_")
      set(l system)
    endif()
    hapi_set_test_label(${t} ${l})
  endforeach()
endfunction()
