// Synthetic StereoLandmarks for the nodelet tests: random 3D points with fixed
// random ORB-sized descriptors, seen from a known smooth camera trajectory;
// each measurement is the point in the camera frame plus Gaussian noise of the
// covariance it is published with.
#pragma once

#include <hapi_msgs/StereoLandmarks.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <sensor_msgs/CameraInfo.h>

#include <Eigen/Geometry>
#include <array>
#include <random>
#include <string>
#include <vector>

namespace hapi_eskf_test {

// A rectified stereo pair's CameraInfo (640 x 480, f 400 px, baseline
// 0.1 m): what the nodelet's ~left/camera_info and ~right/camera_info carry
// (the right P holds Tx = -f * baseline).
sensor_msgs::CameraInfo stereoCameraInfo(bool right, const std::string& frame_id);
constexpr double kCameraInfoFocal = 400.0, kCameraInfoBaseline = 0.1;
// Both, latched, on /eskf/left/camera_info and /eskf/right/camera_info:
// keep the returned publishers for as long as the nodelet may read them.
std::array<ros::Publisher, 2> latchStereoCameraInfo(ros::NodeHandle& nh, const std::string& frame_id);

class SyntheticScene {
 public:
  explicit SyntheticScene(int n_points = 400, unsigned seed = 42, double sigma = 0.003);
  // Camera -> scene-world pose at time t [s] since the start (optical frame: z forward).
  Eigen::Isometry3d pose(double t) const;
  // Every point in front of the camera within a 90x70 degree field of view.
  hapi_msgs::StereoLandmarks frame(double t, const ros::Time& stamp, const std::string& frame_id);

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::array<uint8_t, 32>> descriptors_;
  std::vector<std::array<uint8_t, 3>> colours_;
  std::mt19937 rng_;
  double sigma_;
};

}  // namespace hapi_eskf_test
