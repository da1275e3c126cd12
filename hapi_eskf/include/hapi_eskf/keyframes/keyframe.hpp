// A keyframe for place recognition (docs/DESIGN.md "Keyframes"): a frame's
// stereo points in its camera frame with their covariances and descriptors,
// and the camera's pose in the map frame when it was kept. A camera that
// sees the same points again is placed by matching them (KeyframeRelocaliser).
#pragma once

#include "hapi_eskf/types.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace hapi_eskf {

struct Keyframe {
  std::uint64_t id = 0;                                         // unique, > 0
  double stamp = 0.0;                                           // [s]
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();  // the camera in the map frame
  Mat6 pose_covariance = Mat6::Identity();                      // of [dp, dtheta] in the map frame [m^2, rad^2]
  std::vector<Vec3> points;                                     // in the camera frame [m]
  std::vector<Mat3> point_covariances;                          // [m^2]
  int descriptor_length = 0;                                    // bytes per descriptor
  std::vector<std::uint8_t> descriptors;                        // points.size() * descriptor_length

  std::size_t size() const { return points.size(); }
  const std::uint8_t* descriptor(std::size_t i) const { return descriptors.data() + i * descriptor_length; }
};

// A keyframe from a filtered frame: its measurements and the camera pose the
// filter gave it.
Keyframe keyframeOf(std::uint64_t id, const StereoFrame& frame, const Eigen::Isometry3d& T_map_cam,
                    const Mat6& pose_covariance);

// The keyframe's points as landmarks of the map frame (docs/DESIGN.md
// "Keyframes"): m = p + R z with the covariance of z and of the keyframe's
// pose (rotation error on the right: dm = dp - R [z]x dtheta + R dz), each
// observed once. The points share the pose's error; as landmarks they are
// taken as independent, like a loaded map's.
std::vector<PriorLandmark> keyframeLandmarks(const Keyframe& kf);

}  // namespace hapi_eskf
