#include "hapi_eskf/keyframes/keyframe.hpp"

#include "hapi_eskf/so3.hpp"

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

std::vector<PriorLandmark> keyframeLandmarks(const Keyframe& kf) {
  const Mat3 R = kf.T_map_cam.linear();
  std::vector<PriorLandmark> out(kf.size());
  for (std::size_t i = 0; i < kf.size(); ++i) {
    Eigen::Matrix<double, 3, 6> J;
    J << Mat3::Identity(), -R * skew(kf.points[i]);
    PriorLandmark& l = out[i];
    l.position = kf.T_map_cam * kf.points[i];
    l.covariance = R * kf.point_covariances[i] * R.transpose() + J * kf.pose_covariance * J.transpose();
    l.covariance = 0.5 * (l.covariance + l.covariance.transpose());
    l.times_observed = 1;
    l.descriptor.assign(kf.descriptor(i), kf.descriptor(i) + kf.descriptor_length);
  }
  return out;
}

}  // namespace hapi_eskf
