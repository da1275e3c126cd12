// hapi_sim: writes a Scenario as a EuRoC / ASL data set folder (ROS-free),
// readable by any EuRoC reader:
//   mav0/cam0/data/<ns>.png, cam0/data.csv, cam0/sensor.yaml (cam1 likewise)
//   mav0/imu0/data.csv, imu0/sensor.yaml
//   mav0/state_groundtruth_estimate0/data.csv, sensor.yaml: the body (= IMU)
//       pose, velocity and true biases in the inertial frame, at IMU rate
// plus three non-standard files:
//   mav0/scene.yaml                    the /ground_truth/scene YAML (scene frame)
//   mav0/calibration.yaml              the /ground_truth/calibration YAML
//   mav0/scene_groundtruth0/data.csv   the scene frame in the inertial frame
//       (#timestamp, p_RS_R_x [m], ..., q_RS_z []), at IMU rate; the left
//       camera in the scene follows as T_RS^-1 T_RB T_BC.
// and with an imaging camera (imaging_rate > 0):
//   mav0/cam_imaging/data/<ns>.png, data.csv, sensor.yaml   as cam0's, at its rate
//   mav0/surface_motion_groundtruth0/data.csv   the surface-motion truth at the
//       imaging pixel (kSurfaceMotionHeader), at IMU rate, true clock;
//       sensor.yaml: the pixel and the frame rate of the px/frame columns.
// Stamps: kSimEpochNs + true time for IMU and ground truth, + camera stamp for
// images (the time offset stays in the data, as a real device records it).
#pragma once
#include <fstream>
#include <string>

#include "hapi_sim/scenario.hpp"

namespace hapi_sim {

class AslWriter {
 public:
  // Creates root/mav0/... and the static files; throws std::runtime_error on I/O failure.
  AslWriter(const std::string& root, const Scenario& scenario);
  void addFrame(int64_t k, const cv::Mat& left, const cv::Mat& right);
  void addImu(int64_t i, const ImuReading& reading);
  void addImaging(int64_t j, const cv::Mat& image);
  void close();

  // Column headers, exactly as EuRoC's files.
  static const char* const kCameraHeader;
  static const char* const kImuHeader;
  static const char* const kGroundTruthHeader;
  static const char* const kPoseHeader;
  static const char* const kSurfaceMotionHeader;

 private:
  const Scenario& s_;
  std::string mav_;
  bool imaging_;
  std::ofstream cam_[2], imu_, gt_, scene_gt_, cam_imaging_, surface_gt_;
};

// The whole scenario (renders every frame).
void writeAslDataset(const Scenario& scenario, const std::string& root);

}  // namespace hapi_sim
