// File export for ~save_map (PLY) and ~save_trajectory (TUM). ROS-free.
#pragma once

#include "hapi_eskf/ros/conversions.hpp"

#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

struct StampedPose {
  double stamp = 0.0;  // [s]
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

// ASCII PLY: "element vertex N" with properties float x y z, uchar red green
// blue, float sigma [m] (landmarkSigma). Returns "" on success, else the error.
std::string writePly(const std::string& path, const std::vector<MapPoint>& points);

// TUM RGB-D benchmark trajectory format: one line "t x y z qx qy qz qw" per pose.
std::string writeTum(const std::string& path, const std::vector<StampedPose>& poses);

// "<dir>/<prefix>_YYYYmmdd_HHMMSS_<ms>.<ext>" from the wall clock (UTC).
std::string timestampedPath(const std::string& dir, const std::string& prefix, const std::string& ext);

}  // namespace ros_glue
}  // namespace hapi_eskf
