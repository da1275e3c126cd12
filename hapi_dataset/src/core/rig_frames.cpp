// Frame changes between an ASL recording and the system (rig_frames.hpp).
#include "hapi_dataset/rig_frames.hpp"

#include <stdexcept>

namespace hapi_dataset {

Eigen::Isometry3d cameraInWorld(const Eigen::Isometry3d& T_W_B, const CameraSensor& cam0) {
  return T_W_B * cam0.T_BS;
}

Eigen::Isometry3d imuInCamera(const CameraSensor& cam0, const ImuSensor& imu0) {
  return cam0.T_BS.inverse() * imu0.T_BS;
}

CameraTwist cameraTwistAt(const std::vector<BodyPose>& gt, size_t i, const CameraSensor& cam0) {
  if (gt.size() < 2 || i >= gt.size()) throw std::out_of_range("cameraTwistAt needs two samples and a valid index");
  const size_t a = i == 0 ? 0 : i - 1;
  const size_t b = i + 1 < gt.size() ? i + 1 : i;
  const double dt = (gt[b].stamp_ns - gt[a].stamp_ns) * 1e-9;
  // Body rate in the body frame: R_a^T R_b = Exp(w_B dt).
  const Eigen::AngleAxisd d(gt[a].T_W_B.linear().transpose() * gt[b].T_W_B.linear());
  const Eigen::Vector3d w_B = d.axis() * d.angle() / dt;
  const Eigen::Matrix3d& R_WB = gt[i].T_W_B.linear();
  const Eigen::Vector3d v_W = gt[i].v_W + R_WB * w_B.cross(cam0.T_BS.translation());
  const Eigen::Matrix3d R_W_cam = R_WB * cam0.T_BS.linear();
  CameraTwist t;
  t.linear = R_W_cam.transpose() * v_W;
  t.angular = cam0.T_BS.linear().transpose() * w_B;
  return t;
}

SecNsec toSecNsec(int64_t stamp_ns) {
  if (stamp_ns < 0 || stamp_ns / 1000000000LL > static_cast<int64_t>(UINT32_MAX))
    throw std::out_of_range("timestamp " + std::to_string(stamp_ns) + " ns is outside ROS time");
  return {static_cast<uint32_t>(stamp_ns / 1000000000LL), static_cast<uint32_t>(stamp_ns % 1000000000LL)};
}

}  // namespace hapi_dataset
