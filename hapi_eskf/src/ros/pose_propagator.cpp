// The nodelet's IMU-rate copy of the filter pose (pose_propagator.hpp).
#include "hapi_eskf/ros/pose_propagator.hpp"

#include "hapi_eskf/gyro_prediction.hpp"
#include "hapi_eskf/jacobians.hpp"

namespace hapi_eskf {
namespace ros_glue {

void PosePropagator::rebase(const PoseState& pose, const Mat12& covariance, double stamp) {
  pose_ = pose;
  C_ = covariance;
  time_ = stamp;
  valid_ = true;
}

// The filter's gyro step (gyro_prediction.hpp), applied to the 12x12 pose
// covariance only.
Status PosePropagator::step(double stamp, const Vec3& gyro_camera, double sigma_gyro) {
  if (!valid_) return Status::kNotInitialised;
  return predictWithGyroStep(&pose_, &time_, stamp, gyro_camera, sigma_gyro, settings_,
                             [this](const Mat12& F, const Mat12& Q) {
                               C_ = predictPoseCovariance(C_, F, Q);
                               return Status::kOk;
                             });
}

}  // namespace ros_glue
}  // namespace hapi_eskf
