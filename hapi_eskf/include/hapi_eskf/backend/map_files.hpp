// The map and trajectory file formats (ROS-free): the nodelet's ~save_map
// (PLY) and ~save_trajectory (TUM) and the offline tools (graph_refine) write
// through these, so every map file has one layout.
#pragma once

#include "hapi_eskf/types.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace hapi_eskf {

// Scalar uncertainty of a landmark for the map: sqrt of the LARGEST eigenvalue
// of its 3x3 marginal covariance, i.e. the 1-sigma half-axis of the worst
// direction of its uncertainty ellipsoid [m] (conservative: a point is never
// shown as better known than its weakest direction).
double landmarkSigma(const Mat3& covariance);

// One map point as published and exported.
struct MapPoint {
  Vec3 position = Vec3::Zero();  // in the published world frame [m]
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
  float sigma = 0.f;             // landmarkSigma [m]
  uint32_t id = 0;               // landmark id (lower 32 bits)
};

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

}  // namespace hapi_eskf
