// Constant-velocity pose kinematics and their error-state Jacobians
// (docs/DESIGN.md "Filter"), shared by every back end: the ES-EKF's camera
// motion models, Graph SLAM's and FastSLAM's pose prediction and the
// covariance storages' pose-block step. Every Jacobian here is checked
// against central finite differences in test/test_jacobians.cpp (the
// thesis's printed equations contain typos).
#pragma once

#include "hapi_eskf/backend/motion_settings.hpp"
#include "hapi_eskf/types.hpp"

namespace hapi_eskf {

// Constant-velocity step of length dt (docs/DESIGN.md "Predict"):
//   p <- p + R v dt; R <- R Exp(w dt); v <- Gamma^dt v; w <- Lambda^dt w.
PoseState predictPose(const PoseState& x, double dt, const MotionSettings& s);

// F = d(error after predict) / d(error before), 12 x 12.
Mat12 predictJacobian(const PoseState& x, double dt, const MotionSettings& s);

// Process noise for a step of length dt: random walks on v and w.
Mat12 processNoise(double dt, const MotionSettings& s);

// The same random walks seen on the pose [dp, dtheta] alone, integrated twice
// over dt (sigma^2 dt^3 / 3): the pose noise of back ends without velocity
// states in their estimate (graph, fastslam2).
Mat6 poseRandomWalkNoise(double dt, double sigma_acceleration, double sigma_angular_acceleration);

// The pose block of the covariance after a step: F C F^T + Q, symmetrised so
// that it stays exactly symmetric over many steps. The CPU backend's predict
// and the nodelet's IMU-rate PosePropagator both use it.
PoseMat predictPoseCovariance(const PoseMat& C, const PoseMat& F, const PoseMat& Q);

// One step with a gyro sample (rad/s, camera frame) replacing w: the state
// after dt and the step's error-state F and Q (the gyro motion model,
// camera_motion_model.cpp).
// As an error-state map w <- gyro is dw' = n_gyro: F_rep = diag(I, I, I, 0),
// Q_rep,ww = sigma^2 / dt (white rate noise of density sigma averaged over
// dt); combined with the constant-velocity step F = F_cv F_rep,
// Q = F_cv Q_rep F_cv^T + Q_cv.
void gyroStep(const PoseState& x, const Vec3& gyro_camera, double sigma_gyro, double dt, const MotionSettings& s,
              PoseState* next, Mat12* F, Mat12* Q);

// Injects the pose part of an error-state correction: p += dp,
// q <- q Exp(dtheta), v += dv, w += dw.
void injectPose(PoseState* x, const Eigen::Ref<const Eigen::VectorXd>& dx12);

}  // namespace hapi_eskf
