// A tiny ASL/EuRoC recording written by the tests themselves: the MH_01
// sensor.yaml layout with a small image size, a few stereo frames (one
// unpaired right image), 200 Hz IMU rows and a ground truth of a body that
// moves along +x at 1 m/s while turning about z at 0.5 rad/s.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <string>

namespace hapi_dataset_test {

struct TinyAsl {
  static constexpr int kWidth = 64, kHeight = 48;
  static constexpr int kFrames = 6;                         // stereo pairs (20 Hz)
  static constexpr int64_t kT0 = 1403636579763555584LL;     // first image [ns]
  static constexpr int64_t kFramePeriod = 50000000LL;       // [ns]
  static constexpr int64_t kImuPeriod = 5000000LL;          // [ns]
  static constexpr int kImuRows = 62;                       // from kT0 - 5 ms
  static constexpr double kSpeed = 1.0;                     // [m/s] along world x
  static constexpr double kYawRate = 0.5;                   // [rad/s] about world z

  // The rig: cam0 of EuRoC MH_01, cam1 = cam0 shifted 0.11 m along its x and
  // turned 1 degree about its y axis (the known rotation between cameras).
  static Eigen::Isometry3d T_BS_cam0();
  static Eigen::Isometry3d T_BS_cam1();

  // Grey level of pixel (x, y) of frame k (camera 0 or 1).
  static uint8_t pixel(int k, int camera, int x, int y);
  static Eigen::Isometry3d bodyPose(int64_t stamp_ns);  // T_W_B
};

// Writes the recording under `root`/mav0 (root created if needed); with_truth
// adds state_groundtruth_estimate0, scene adds mav0/scene.yaml with that text.
void writeTinyAsl(const std::string& root, bool with_truth, const std::string& scene = "");

// A fresh empty folder under the system's temporary directory.
std::string makeTempDir(const std::string& tag);

}  // namespace hapi_dataset_test
