// The IMU-rate propagation copy must equal the filter after the same IMU
// samples (pose, pose-block covariance and the camera covariance of the
// outputs), for the gyro and the inertial model, and reject what the filter
// rejects; after a frame in which the scene moved, it follows the surface
// (the frame-to-frame camera motion) instead of the IMU.
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/pose_propagator.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using hapi_eskf::CameraExtrinsic;
using hapi_eskf::Eskf;
using hapi_eskf::EskfSettings;
using hapi_eskf::ImuSample;
using hapi_eskf::Mat12;
using hapi_eskf::MotionModelKind;
using hapi_eskf::PoseMat;
using hapi_eskf::PoseState;
using hapi_eskf::Status;
using hapi_eskf::Vec3;
using hapi_eskf::PosePropagator;

namespace {

ImuSample sampleAt(double t) {
  return ImuSample{t, Vec3(0.3 * std::sin(2.0 * t), -0.2 + 0.1 * t, 0.5 * std::cos(3.0 * t)),
                   Vec3(0.2 * std::cos(t), 9.81 + 0.1 * std::sin(4.0 * t), 0.3)};
}

class PosePropagatorModels : public testing::TestWithParam<MotionModelKind> {};

}  // namespace

TEST_P(PosePropagatorModels, EqualsTheFilterAfterTheSameImuSamples) {
  EskfSettings s;
  s.max_landmarks = 100;
  s.max_update_landmarks = 50;
  s.motion_model = GetParam();
  s.velocity_damping = 0.9;  // exercise the damping terms too
  s.angular_velocity_damping = 0.8;
  s.gyro_noise_density = 1.7e-3;
  ASSERT_EQ(s.validate(), "");
  CameraExtrinsic e;
  e.R_imu_cam = Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX()).toRotationMatrix();
  e.p_imu_cam = Vec3(0.02, -0.01, 0.03);
  Eskf eskf(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32, hapi_eskf::filterPoseDim(s)), e);
  PoseState x0;
  x0.p = Vec3(0.1, -0.2, 0.3);
  x0.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  x0.v = Vec3(0.5, 0.0, -0.3);
  x0.w = Vec3(0.0, 0.2, 0.1);
  ASSERT_EQ(eskf.reset(x0, 10.0), Status::kOk);
  double t = 10.0;
  while (eskf.awaitingAlignment()) {  // inertial: the gravity alignment first
    t += 0.005;
    ASSERT_EQ(eskf.addImu(sampleAt(t)), Status::kOk);
  }
  ASSERT_EQ(eskf.predictTo(t + 0.1), Status::kOk);  // correlated pose covariance
  t += 0.1;

  PosePropagator prop(s);
  prop.rebase(eskf);
  const PoseState start = prop.pose();
  for (int i = 1; i <= 50; ++i) {
    const ImuSample m = sampleAt(t + 0.01 * i);
    ASSERT_EQ(eskf.addImu(m), Status::kOk);
    ASSERT_EQ(prop.step(m), Status::kOk);
  }
  EXPECT_DOUBLE_EQ(prop.time(), eskf.time());
  EXPECT_LT((prop.pose().p - eskf.pose().p).norm(), 1e-12);
  EXPECT_LT(prop.pose().q.angularDistance(eskf.pose().q), 1e-12);
  EXPECT_LT((prop.pose().v - eskf.pose().v).norm(), 1e-12);
  EXPECT_LT((prop.pose().w - eskf.pose().w).norm(), 1e-12);
  const PoseMat C = eskf.poseCovariance();
  EXPECT_EQ(prop.covariance().rows(), hapi_eskf::poseDim(s));
  EXPECT_LT((prop.covariance() - C).norm(), 1e-12 * C.norm()) << prop.covariance() - C;
  const Mat12 Cc = eskf.cameraCovariance();
  EXPECT_LT((prop.cameraCovariance() - Cc).norm(), 1e-12 * Cc.norm());
  // The rotation really moved (the comparison is not between two no-ops).
  EXPECT_GT(prop.pose().q.angularDistance(start.q), 0.01);
}

INSTANTIATE_TEST_SUITE_P(ImuModels, PosePropagatorModels,
                         testing::Values(MotionModelKind::kGyro, MotionModelKind::kInertial));

TEST(PosePropagator, RejectsWhatTheFilterRejects) {
  EskfSettings s;
  s.motion_model = MotionModelKind::kGyro;
  PosePropagator prop(s);
  EXPECT_FALSE(prop.valid());
  EXPECT_EQ(prop.step(ImuSample{1.0, Vec3::Zero(), Vec3::Zero()}), Status::kNotInitialised);
  Eskf eskf(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32, hapi_eskf::filterPoseDim(s)));
  ASSERT_EQ(eskf.reset(PoseState(), 1.0), Status::kOk);
  prop.rebase(eskf);
  const PoseMat C = prop.covariance();
  EXPECT_EQ(prop.step(ImuSample{0.99, Vec3::Zero(), Vec3::Zero()}), Status::kInvalidArgument);  // before time()
  EXPECT_EQ(prop.step(ImuSample{1.01, Vec3(NAN, 0, 0), Vec3::Zero()}), Status::kNonFinite);
  EXPECT_EQ(prop.step(ImuSample{1.01, Vec3::Zero(), Vec3(0, NAN, 0)}), Status::kNonFinite);
  EXPECT_DOUBLE_EQ(prop.time(), 1.0);  // unchanged by the failures
  EXPECT_EQ((prop.covariance() - C).norm(), 0.0);
  EXPECT_EQ(prop.step(ImuSample{1.0, Vec3::Zero(), Vec3::Zero()}), Status::kOk);  // dt = 0: no-op
  EXPECT_EQ(prop.step(ImuSample{1.02, Vec3(0, 0, 1), Vec3::Zero()}), Status::kOk);
  EXPECT_NEAR(prop.pose().q.angularDistance(Eigen::Quaterniond::Identity()), 0.02, 1e-9);
  prop.invalidate();
  EXPECT_EQ(prop.step(ImuSample{1.03, Vec3::Zero(), Vec3::Zero()}), Status::kNotInitialised);
}

// Surface-relative mode: the twist is the motion between the two latest
// filter poses, the pose extrapolates it, the IMU samples only move the clock.
TEST(PosePropagator, FollowsTheSurfaceAfterAFrameWithSceneMotion) {
  EskfSettings s;
  s.motion_model = MotionModelKind::kGyro;
  Eskf eskf(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32, hapi_eskf::filterPoseDim(s)));
  PoseState a, b;
  a.p = Vec3(0.1, 0.2, 0.3);
  a.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec3(0, 1, 1).normalized()));
  b.p = Vec3(0.12, 0.19, 0.31);
  b.q = a.q * Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Vec3(1, 0, 0)));
  PosePropagator prop(s);
  ASSERT_EQ(eskf.reset(a, 1.0), Status::kOk);
  prop.rebase(eskf, true);  // no previous frame: nothing to difference, IMU mode
  EXPECT_FALSE(prop.surfaceRelative());
  ASSERT_EQ(eskf.reset(b, 1.1), Status::kOk);
  prop.rebase(eskf, true);
  ASSERT_TRUE(prop.surfaceRelative());
  const Vec3 v = b.q.conjugate() * (b.p - a.p) / 0.1, w = Vec3(0.2, 0, 0);
  EXPECT_LT((prop.pose().v - v).norm(), 1e-9);
  EXPECT_LT((prop.pose().w - w).norm(), 1e-9);
  const Mat12 C0 = prop.cameraCovariance();
  // A gyro sample that says "turning about z" does not move the surface-relative pose that way.
  ASSERT_EQ(prop.step(ImuSample{1.15, Vec3(0, 0, 2.0), Vec3::Zero()}), Status::kOk);
  EXPECT_LT((prop.pose().p - (b.p + b.q * (v * 0.05))).norm(), 1e-9);
  const Eigen::Quaterniond q_expected = b.q * Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * 0.05, Vec3::UnitX()));
  EXPECT_LT(prop.pose().q.angularDistance(q_expected), 1e-9);
  EXPECT_GT(prop.cameraCovariance()(0, 0), C0(0, 0));  // the extrapolation's uncertainty grows
  EXPECT_EQ(prop.step(ImuSample{1.16, Vec3(NAN, 0, 0), Vec3::Zero()}), Status::kNonFinite);
  EXPECT_EQ(prop.step(ImuSample{1.14, Vec3::Zero(), Vec3::Zero()}), Status::kInvalidArgument);
  // The next frame without scene motion: back to the IMU.
  ASSERT_EQ(eskf.reset(b, 1.2), Status::kOk);
  prop.rebase(eskf, false);
  EXPECT_FALSE(prop.surfaceRelative());
  ASSERT_EQ(prop.step(ImuSample{1.21, Vec3(0, 0, 2.0), Vec3::Zero()}), Status::kOk);
  EXPECT_GT(prop.pose().q.angularDistance(b.q), 0.015);
}

// A velocity no frame has measured (the start's guess of rest) gives no
// IMU-rate output; the second frame, updated against the map of the first,
// measures it, and so does a still start. The copy steps either way.
TEST(PosePropagator, PublishesOnlyAMeasuredVelocity) {
  EskfSettings s;
  s.max_landmarks = 100;
  s.max_update_landmarks = 50;
  s.motion_model = MotionModelKind::kGyro;
  ASSERT_EQ(s.validate(), "");
  Eskf gyro(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32, hapi_eskf::filterPoseDim(s)));
  ASSERT_EQ(gyro.reset(PoseState(), 1.0), Status::kOk);
  PosePropagator prop(s);
  prop.rebase(gyro);
  EXPECT_TRUE(prop.valid());
  EXPECT_FALSE(prop.publishable());
  std::mt19937 rng(7);
  const hapi_eskf::sim::World world = hapi_eskf::sim::randomWorld(rng, 60, Vec3(-2, -1.5, 3), Vec3(2, 1.5, 6));
  const hapi_eskf::sim::StereoRig rig;
  hapi_eskf::IterationReport rep;
  ASSERT_EQ(gyro.processFrame(hapi_eskf::sim::makeFrame(world, PoseState(), rig, 1.1, 0, rng), &rep), Status::kOk);
  ASSERT_EQ(rep.n_updated, 0);  // the first frame only builds the map
  prop.rebase(gyro);
  EXPECT_FALSE(prop.publishable());
  EXPECT_EQ(prop.step(ImuSample{1.15, Vec3(0, 0, 0.1), Vec3::Zero()}), Status::kOk);
  ASSERT_EQ(gyro.processFrame(hapi_eskf::sim::makeFrame(world, PoseState(), rig, 1.2, 0, rng), &rep), Status::kOk);
  ASSERT_GT(rep.n_updated, 10);
  prop.rebase(gyro);
  EXPECT_TRUE(prop.publishable());
  prop.invalidate();
  EXPECT_FALSE(prop.publishable());
  ASSERT_EQ(gyro.reset(PoseState(), 2.0), Status::kOk);  // a restart guesses again
  prop.rebase(gyro);
  EXPECT_FALSE(prop.publishable());

  // Inertial: a still start measures a zero velocity, a moving one does not.
  s.motion_model = MotionModelKind::kInertial;
  for (const bool still : {true, false}) {
    Eskf inertial(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32, hapi_eskf::filterPoseDim(s)));
    ASSERT_EQ(inertial.reset(PoseState(), 1.0), Status::kOk);
    double t = 1.0;
    while (inertial.awaitingAlignment()) {
      t += 0.005;
      ASSERT_EQ(inertial.addImu(still ? ImuSample{t, Vec3::Zero(), Vec3(0, 0, s.gravity_magnitude)} : sampleAt(t)),
                Status::kOk);
    }
    PosePropagator p(s);
    p.rebase(inertial);
    EXPECT_EQ(p.publishable(), still);
  }
}
