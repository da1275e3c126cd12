// The IMU-rate propagation copy must equal the filter after the same gyro
// samples (pose and 12x12 pose covariance), and reject what the filter rejects.
#include "hapi_eskf/eskf.hpp"
#include "hapi_eskf/ros/pose_propagator.hpp"

#include <gtest/gtest.h>

#include <cmath>

using hapi_eskf::Eskf;
using hapi_eskf::EskfSettings;
using hapi_eskf::Mat12;
using hapi_eskf::PoseState;
using hapi_eskf::Status;
using hapi_eskf::Vec3;
using hapi_eskf::ros_glue::PosePropagator;

namespace {

Vec3 gyroAt(double t) { return Vec3(0.3 * std::sin(2.0 * t), -0.2 + 0.1 * t, 0.5 * std::cos(3.0 * t)); }

}  // namespace

TEST(PosePropagator, EqualsTheFilterAfterTheSameGyroSamples) {
  EskfSettings s;
  s.max_landmarks = 100;
  s.max_update_landmarks = 50;
  s.velocity_damping = 0.9;  // exercise the damping terms too
  s.angular_velocity_damping = 0.8;
  ASSERT_EQ(s.validate(), "");
  Eskf eskf(s, hapi_eskf::makeCpuBackend(s.max_landmarks, 32));
  PoseState x0;
  x0.p = Vec3(0.1, -0.2, 0.3);
  x0.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  x0.v = Vec3(0.5, 0.0, -0.3);
  x0.w = Vec3(0.0, 0.2, 0.1);
  ASSERT_EQ(eskf.reset(x0, 10.0), Status::kOk);
  ASSERT_EQ(eskf.predictTo(10.1), Status::kOk);  // correlated pose covariance

  PosePropagator prop(s);
  prop.rebase(eskf.pose(), eskf.poseCovariance(), eskf.time());
  const double sigma = 1.7e-3;
  for (int i = 1; i <= 50; ++i) {
    const double t = 10.1 + 0.01 * i;
    ASSERT_EQ(eskf.predictWithGyro(t, gyroAt(t), sigma), Status::kOk);
    ASSERT_EQ(prop.step(t, gyroAt(t), sigma), Status::kOk);
  }
  EXPECT_DOUBLE_EQ(prop.time(), eskf.time());
  EXPECT_LT((prop.pose().p - eskf.pose().p).norm(), 1e-12);
  EXPECT_LT(prop.pose().q.angularDistance(eskf.pose().q), 1e-12);
  EXPECT_LT((prop.pose().v - eskf.pose().v).norm(), 1e-12);
  EXPECT_LT((prop.pose().w - eskf.pose().w).norm(), 1e-12);
  const Mat12 C = eskf.poseCovariance();
  EXPECT_LT((prop.covariance() - C).norm(), 1e-12 * C.norm()) << prop.covariance() - C;
  // The rotation really moved (the comparison is not between two no-ops).
  EXPECT_GT(prop.pose().q.angularDistance(x0.q), 0.01);
}

TEST(PosePropagator, RejectsWhatTheFilterRejects) {
  EskfSettings s;
  PosePropagator prop(s);
  EXPECT_FALSE(prop.valid());
  EXPECT_EQ(prop.step(1.0, Vec3::Zero(), 1e-3), Status::kNotInitialised);
  Mat12 C = Mat12::Identity() * 1e-4;
  prop.rebase(PoseState(), C, 1.0);
  EXPECT_EQ(prop.step(0.99, Vec3::Zero(), 1e-3), Status::kInvalidArgument);  // before time()
  EXPECT_EQ(prop.step(1.01, Vec3(NAN, 0, 0), 1e-3), Status::kNonFinite);
  EXPECT_EQ(prop.step(1.01, Vec3::Zero(), 0.0), Status::kInvalidArgument);
  EXPECT_DOUBLE_EQ(prop.time(), 1.0);  // unchanged by the failures
  EXPECT_EQ((prop.covariance() - C).norm(), 0.0);
  EXPECT_EQ(prop.step(1.0, Vec3::Zero(), 1e-3), Status::kOk);  // dt = 0: no-op
  EXPECT_EQ(prop.step(1.02, Vec3(0, 0, 1), 1e-3), Status::kOk);
  EXPECT_NEAR(prop.pose().q.angularDistance(Eigen::Quaterniond::Identity()), 0.02, 1e-9);
  prop.invalidate();
  EXPECT_EQ(prop.step(1.03, Vec3::Zero(), 1e-3), Status::kNotInitialised);
}
