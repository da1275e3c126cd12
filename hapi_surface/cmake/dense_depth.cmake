# Dense depth (docs/DESIGN.md "Dense depth"):
#  hapi_surface_block_match: OpenCV-free (builds on the GPU machine too): the
#    block matcher's CPU reference and, with nvcc, its CUDA kernel, and
#    their CPU == GPU gtest;
#  hapi_surface_depth: the core (SGBM matcher, rectifier), needs OpenCV;
#    its gtests; with catkin the DenseDepthNodelet and dense_depth_link.
# The settings tables use hapi_eskf's field table (header only) and
# hapi_dataset's CameraInfoData (header only).
add_library(hapi_surface_block_match src/core/dense_depth_block_match.cpp)
target_include_directories(hapi_surface_block_match PUBLIC
  $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
# No FMA contraction: the CPU reference's arithmetic is the kernel's.
target_compile_options(hapi_surface_block_match PRIVATE -ffp-contract=off)
if(HAPI_CUDA_FOUND)
  add_library(hapi_surface_block_match_cuda_objs OBJECT src/cuda/dense_depth_block_match.cu)
  target_include_directories(hapi_surface_block_match_cuda_objs PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
  target_link_libraries(hapi_surface_block_match_cuda_objs PUBLIC CUDA::cudart)
  target_compile_options(hapi_surface_block_match_cuda_objs PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false>)
  target_sources(hapi_surface_block_match PRIVATE $<TARGET_OBJECTS:hapi_surface_block_match_cuda_objs>)
  target_compile_definitions(hapi_surface_block_match PUBLIC HAPI_SURFACE_WITH_CUDA)
  target_link_libraries(hapi_surface_block_match PUBLIC CUDA::cudart)
  hapi_add_core_gtest(hapi_surface_dense_depth_cuda_test SOURCES test/test_dense_depth_cuda.cpp
                      LIBS hapi_surface_block_match)
endif()

set(_hapi_surface_opencv_mode QUIET)
if(catkin_FOUND)
  set(_hapi_surface_opencv_mode REQUIRED)
endif()
find_package(OpenCV ${_hapi_surface_opencv_mode} COMPONENTS core imgproc calib3d)
if(OpenCV_FOUND)
  add_library(hapi_surface_depth
    src/core/dense_depth.cpp src/core/dense_depth_settings.cpp src/core/dense_depth_rectifier.cpp)
  target_include_directories(hapi_surface_depth PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>
    $<BUILD_INTERFACE:${hapi_eskf_SOURCE_DIR}/include> $<BUILD_INTERFACE:${hapi_dataset_SOURCE_DIR}/include>)
  target_link_libraries(hapi_surface_depth PUBLIC hapi_surface_block_match hapi_nodelet_kit_headers ${OpenCV_LIBS})
  hapi_add_core_gtest(hapi_surface_dense_depth_test SOURCES test/test_dense_depth.cpp test/test_dense_depth_block_match.cpp
                      LIBS hapi_surface_depth)
  # On the simulator's rendered skin scene against its true depth.
  if(TARGET hapi_sim_render)
    hapi_add_core_gtest(hapi_surface_dense_depth_sim_test SOURCES test/test_dense_depth_sim.cpp
                        LIBS hapi_surface_depth hapi_sim_render)
  endif()
endif()

if(catkin_FOUND)
  # The nodelet (src/ros) reuses the front end's image conversion
  # (hapi_frontend_ros_conv: toGrey, the pair's size checks, ReasonThrottle) and
  # hapi_dataset's message conversions.
  include_directories(SYSTEM ${catkin_INCLUDE_DIRS})
  # Parameters and the keyframe processing, shared by the nodelet and the tool.
  add_library(hapi_surface_dense_depth_ros STATIC
    src/ros/dense_depth_nodelet_params.cpp src/ros/dense_depth_nodelet_processor.cpp)
  target_include_directories(hapi_surface_dense_depth_ros PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/src/ros)
  target_link_libraries(hapi_surface_dense_depth_ros PUBLIC hapi_surface_depth hapi_frontend_ros_conv hapi_dataset_bag_messages
    hapi_nodelet_kit
    ${catkin_LIBRARIES})
  add_library(hapi_surface_dense_depth_nodelet
    src/ros/dense_depth_nodelet.cpp src/ros/dense_depth_nodelet_diagnostics.cpp)
  target_link_libraries(hapi_surface_dense_depth_nodelet PRIVATE hapi_surface_dense_depth_ros)
  # Bytes per second of the depth topics on a recording (docs/DESIGN.md "Dense depth", link).
  add_executable(dense_depth_link src/tools/dense_depth_link.cpp)
  target_link_libraries(dense_depth_link PRIVATE hapi_surface_dense_depth_ros)
  install(TARGETS hapi_surface_block_match hapi_surface_depth hapi_surface_dense_depth_nodelet dense_depth_link
    ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
    LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
    RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
  install(FILES dense_depth_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
  if(CATKIN_ENABLE_TESTING)
    # The nodelet on synthetic pairs: depth, header, bad input, invalid parameters.
    find_package(rostest REQUIRED)
    add_rostest(test/ros/dense_depth_nodelet.test DEPENDENCIES hapi_surface_dense_depth_nodelet)
    install(PROGRAMS test/ros/dense_depth_nodelet_test.py DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
    hapi_label_tests(unit)
  endif()
endif()
