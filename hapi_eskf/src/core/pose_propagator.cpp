// The IMU-rate copy of the filter state (pose_propagator.hpp).
#include "hapi_eskf/pose_propagator.hpp"

#include "hapi_eskf/jacobians.hpp"

namespace hapi_eskf {

void PosePropagator::rebase(const Eskf& filter) {
  model_ = makeMotionModel(settings_, filter.motionModel().extrinsic());
  x_ = filter.state();
  C_ = filter.poseCovariance();
  time_ = filter.time();
}

// The filter's step (motion_model.hpp predictStep), applied to the pose
// block's covariance only.
Status PosePropagator::step(const ImuSample& sample) {
  if (!model_) return Status::kNotInitialised;
  return predictStep(*model_, &x_, &time_, sample.stamp, &sample, [this](const PoseMat& F, const PoseMat& Q) {
    C_ = predictPoseCovariance(C_, F, Q);
    return Status::kOk;
  });
}

PoseState PosePropagator::pose() const { return model_ ? model_->camera(x_) : PoseState(); }

Mat12 PosePropagator::cameraCovariance() const {
  return model_ ? hapi_eskf::cameraCovariance(*model_, x_, C_) : Mat12::Zero();
}

}  // namespace hapi_eskf
