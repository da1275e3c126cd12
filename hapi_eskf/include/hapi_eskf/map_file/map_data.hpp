// The content of a saved landmark map (docs/DESIGN.md "Map file"): what a
// later session needs to relocalise in it without a pose hint. Plain data,
// ROS-free; map_writer.hpp encodes it, map_reader.hpp decodes and checks it.
#pragma once

#include "hapi_eskf/keyframes/keyframe.hpp"
#include "hapi_eskf/types.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace map_file {

// Descriptor encodings, numbered as hapi_msgs/StereoLandmarks' descriptor_type.
constexpr uint8_t kDescriptorOrb = 0;    // rBRIEF, 32 bytes, Hamming
constexpr uint8_t kDescriptorAkaze = 1;  // M-LDB, 61 bytes, Hamming
// Bytes per descriptor of a known type; 0 for an unknown type.
uint32_t descriptorLengthOf(uint8_t descriptor_type);

// The stereo calibration the map was made with: the rectified left camera
// (pixels), the baseline and, with an IMU, the camera-IMU extrinsic.
struct MapCalibration {
  uint32_t width = 0, height = 0;  // [px]
  double fx = 0, fy = 0, cx = 0, cy = 0;  // [px]
  double baseline = 0;                    // [m], > 0
  bool has_imu = false;
  CameraExtrinsic imu_cam;                // T_imu_cam (types.hpp); identity without IMU
};

// One landmark of the map, in the map frame.
struct MapLandmark {
  uint64_t id = 0;                      // unique in the map, > 0
  Vec3 position = Vec3::Zero();         // [m]
  Mat3 covariance = Mat3::Identity();   // marginal [m^2], symmetric positive definite
  uint32_t times_observed = 1;          // >= 1
  std::vector<uint8_t> descriptor;      // descriptor_length bytes
};

struct MapData {
  std::string map_frame = "map";                      // the frame of every position
  std::string camera_frame;                           // the measurements' frame (left optical)
  // Unit direction of gravity in the map frame; zero when the session had no
  // IMU (the map frame is then the first camera pose, z forward: "Frames").
  Vec3 gravity_direction = Vec3::Zero();
  double created = 0.0;                               // Unix time of the save [s]
  MapCalibration calibration;
  uint8_t descriptor_type = kDescriptorOrb;
  uint32_t descriptor_length = 32;
  std::vector<MapLandmark> landmarks;
  // Keyframes for place recognition (optional section), their descriptors
  // of the landmarks' type and length.
  std::vector<Keyframe> keyframes;
};

}  // namespace map_file
}  // namespace hapi_eskf
