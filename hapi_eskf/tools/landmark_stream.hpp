// The text stream that dump_frames.py writes from a bag and eskf_replay
// reads (ROS-free): front-end frames, IMU samples, the camera-IMU extrinsic,
// ground truth and the scene. Line formats: dump_frames.py's docstring.
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/types.hpp"

#include <optional>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace tools {

struct TruePose {
  double t = 0.0;
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // left camera -> world
};

struct TrueTwist {
  double t = 0.0;
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();  // camera frame
};

struct LandmarkStream {
  std::vector<StereoFrame> frames;
  std::vector<ImuSample> imu;  // IMU frame, stamps on the IMU clock (as recorded)
  std::optional<CameraExtrinsic> extrinsic;
  std::vector<TruePose> truth;
  std::vector<TrueTwist> true_twist;
  bool has_globe = false;
  Vec3 globe_centre = Vec3::Zero();
  double globe_radius = 0.0;
  std::string scene_json;  // empty when the bag had no /ground_truth/scene
};

// Reads `path`; false with *error on a malformed line or an unreadable file.
bool readLandmarkStream(const std::string& path, LandmarkStream* out, std::string* error);

}  // namespace tools
}  // namespace hapi_eskf
