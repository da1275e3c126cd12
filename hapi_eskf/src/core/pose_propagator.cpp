// The IMU-rate copy of the filter state (pose_propagator.hpp).
#include "hapi_eskf/pose_propagator.hpp"

#include "hapi_eskf/jacobians.hpp"

namespace hapi_eskf {

void PosePropagator::rebase(const SlamBackend& filter) {
  PoseBlockState s;
  if (!filter.poseBlockState(&s)) {
    model_.reset();
    return;
  }
  model_ = makeMotionModel(settings_, s.extrinsic);
  x_ = s.x;
  C_ = s.C;
  time_ = s.time;
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
