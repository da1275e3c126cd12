#include "hapi_eskf/keyframes/keyframe.hpp"

namespace hapi_eskf {

Keyframe keyframeOf(std::uint64_t id, const StereoFrame& frame, const Eigen::Isometry3d& T_map_cam,
                    const Mat6& pose_covariance) {
  Keyframe kf;
  kf.id = id;
  kf.stamp = frame.stamp;
  kf.T_map_cam = T_map_cam;
  kf.pose_covariance = pose_covariance;
  kf.descriptor_length = frame.descriptor_length;
  kf.descriptors = frame.descriptors;
  kf.points.reserve(frame.measurements.size());
  kf.point_covariances.reserve(frame.measurements.size());
  for (const StereoMeasurement& m : frame.measurements) {
    kf.points.push_back(m.z);
    kf.point_covariances.push_back(m.Cz);
  }
  return kf;
}

}  // namespace hapi_eskf
