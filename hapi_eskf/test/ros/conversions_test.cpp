// Covariance mapping (filter error state -> ROS 6x6) and the map cloud layout.
#include "hapi_eskf/ros/conversions.hpp"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstring>
#include <random>

using namespace hapi_eskf;
using namespace hapi_eskf::ros_glue;

namespace {
Eigen::Matrix<double, 6, 6> rosCov(const boost::array<double, 36>& c) {
  Eigen::Matrix<double, 6, 6> m;
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < 6; ++k) m(r, k) = c[6 * r + k];
  return m;
}
Vec3 rotLog(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}
}  // namespace

TEST(Conversions, StereoFrameCopiesEverything) {
  hapi_msgs::StereoLandmarks m;
  m.header.stamp.fromSec(12.5);
  m.descriptor_length = 2;
  m.descriptors = {1, 2, 3, 4};
  m.landmarks.resize(2);
  m.landmarks[1].id = 7;
  m.landmarks[1].position.x = 1;
  m.landmarks[1].position.y = 2;
  m.landmarks[1].position.z = 3;
  m.landmarks[1].position_covariance = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  m.landmarks[1].response = 4.5f;
  m.landmarks[1].r = 10;
  m.landmarks[1].g = 20;
  m.landmarks[1].b = 30;
  const StereoFrame f = toStereoFrame(m);
  EXPECT_DOUBLE_EQ(f.stamp, 12.5);
  EXPECT_EQ(f.descriptor_length, 2);
  EXPECT_EQ(f.descriptors, m.descriptors);
  ASSERT_EQ(f.measurements.size(), 2u);
  EXPECT_EQ(f.measurements[1].z, Vec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(f.measurements[1].Cz(0, 1), 2.0);  // row-major
  EXPECT_DOUBLE_EQ(f.measurements[1].Cz(1, 0), 4.0);
  EXPECT_EQ(f.measurements[1].frontend_id, 7u);
  EXPECT_FLOAT_EQ(f.measurements[1].response, 4.5f);
  EXPECT_EQ(f.measurements[1].rgb[2], 30);
}

// Monte-Carlo check of the documented mapping: sample the filter's error state
// (dp world, dtheta LOCAL), apply it to the nominal pose, express the sampled
// poses in map, and compare their empirical covariance in ROS's convention
// (position, rotation about the fixed map axes) with toPoseWithCovariance.
TEST(Conversions, PoseCovarianceMatchesSampledPerturbations) {
  PoseState pose;
  pose.p = Vec3(1, -2, 0.5);
  pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vec3(0.3, -1, 0.4).normalized()));
  Eigen::Isometry3d T_mw = Eigen::Isometry3d::Identity();
  T_mw.linear() = Eigen::AngleAxisd(-1.2, Vec3(1, 0.2, 0).normalized()).toRotationMatrix();
  T_mw.translation() = Vec3(0.1, 0.2, 0.3);
  // A correlated, anisotropic 12x12 covariance.
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, 12, 12> A;
  for (int i = 0; i < 144; ++i) A.data()[i] = n01(rng);
  Mat12 C = 1e-4 * (A * A.transpose()) + 1e-6 * Mat12::Identity();

  const geometry_msgs::PoseWithCovariance out = toPoseWithCovariance(pose, C, T_mw);
  const Vec3 p_m = T_mw * pose.p;
  const Mat3 R_mc = T_mw.linear() * pose.q.toRotationMatrix();
  EXPECT_NEAR(out.pose.position.x, p_m.x(), 1e-12);
  const Eigen::Quaterniond q_out(out.pose.orientation.w, out.pose.orientation.x, out.pose.orientation.y,
                                 out.pose.orientation.z);
  EXPECT_LT(rotLog(q_out.toRotationMatrix().transpose() * R_mc).norm(), 1e-12);

  Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(C.block<6, 6>(0, 0));
  const Eigen::Matrix<double, 6, 6> L = llt.matrixL();
  Eigen::Matrix<double, 6, 6> emp = Eigen::Matrix<double, 6, 6>::Zero();
  const int N = 40000;
  for (int s = 0; s < N; ++s) {
    Eigen::Matrix<double, 6, 1> e;
    for (int i = 0; i < 6; ++i) e(i) = n01(rng);
    e = L * e;
    const Vec3 p = pose.p + e.head<3>();
    const Mat3 R = pose.q.toRotationMatrix() * Eigen::AngleAxisd(e.tail<3>().norm(), e.tail<3>().normalized()).toRotationMatrix();
    Eigen::Matrix<double, 6, 1> d;
    d.head<3>() = T_mw * p - p_m;
    d.tail<3>() = rotLog(T_mw.linear() * R * R_mc.transpose());  // global (fixed-axis) rotation error
    emp += d * d.transpose() / N;
  }
  const Eigen::Matrix<double, 6, 6> got = rosCov(out.covariance);
  EXPECT_LT((got - emp).norm() / got.norm(), 0.03) << "mapped\n" << got << "\nsampled\n" << emp;
  // The naive copy of the local block would be wrong (guards the test itself).
  EXPECT_GT((C.block<6, 6>(0, 0) - emp).norm() / emp.norm(), 0.1);
}

TEST(Conversions, TwistCovarianceIsTheVelocityBlock) {
  PoseState pose;
  pose.v = Vec3(1, 2, 3);
  pose.w = Vec3(-0.1, 0.2, -0.3);
  Mat12 C = Mat12::Zero();
  for (int i = 0; i < 12; ++i) C(i, i) = i + 1;
  C(6, 10) = C(10, 6) = 0.5;
  const auto t = toTwistWithCovariance(pose, C);
  EXPECT_DOUBLE_EQ(t.twist.linear.z, 3);
  EXPECT_DOUBLE_EQ(t.twist.angular.x, -0.1);
  EXPECT_DOUBLE_EQ(t.covariance[0], 7);    // vx
  EXPECT_DOUBLE_EQ(t.covariance[35], 12);  // wz
  EXPECT_DOUBLE_EQ(t.covariance[6 * 0 + 4], 0.5);
}

TEST(Conversions, LandmarkSigmaIsWorstAxis) {
  Mat3 C = Vec3(1e-4, 9e-4, 4e-4).asDiagonal();
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  EXPECT_NEAR(landmarkSigma(R * C * R.transpose()), 0.03, 1e-12);
}

TEST(Conversions, PointCloudLayout) {
  std::vector<LandmarkInfo> lms(2);
  lms[0].id = 5;
  lms[0].position = Vec3(1, 2, 3);
  lms[0].covariance = Mat3::Identity() * 0.04;
  lms[0].rgb = {{255, 128, 1}};
  lms[1].id = (1ull << 32) + 9;  // ids are published modulo 2^32
  lms[1].position = Vec3(-1, 0, 4);
  lms[1].covariance = Mat3::Identity() * 0.01;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Vec3(0, 0, 1);
  const auto cloud = toPointCloud2(toMapPoints(lms, T));
  ASSERT_EQ(cloud.width * cloud.height, 2u);
  std::vector<std::string> names;
  for (const auto& f : cloud.fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"x", "y", "z", "rgb", "sigma", "id"}));
  EXPECT_EQ(cloud.fields[5].datatype, sensor_msgs::PointField::UINT32);
  sensor_msgs::PointCloud2ConstIterator<float> z(cloud, "z"), rgb(cloud, "rgb"), sigma(cloud, "sigma");
  sensor_msgs::PointCloud2ConstIterator<uint32_t> id(cloud, "id");
  EXPECT_FLOAT_EQ(*z, 4.f);
  uint32_t packed;
  std::memcpy(&packed, &*rgb, 4);
  EXPECT_EQ(packed, 0xFF8001u);
  EXPECT_FLOAT_EQ(*sigma, 0.2f);
  EXPECT_EQ(*id, 5u);
  ++id, ++sigma;
  EXPECT_EQ(*id, 9u);
  EXPECT_FLOAT_EQ(*sigma, 0.1f);
}

// An empty map (the snapshot right after a reset) is a valid cloud with the
// same fields and no points; iterating its empty buffer would be undefined
// behaviour (found by tools/sanitize.sh asan).
TEST(Conversions, EmptyMapIsAnEmptyCloudWithTheFields) {
  const auto cloud = toPointCloud2({});
  EXPECT_EQ(cloud.height, 1u);
  EXPECT_EQ(cloud.width, 0u);
  EXPECT_TRUE(cloud.data.empty());
  ASSERT_EQ(cloud.fields.size(), 6u);
  EXPECT_EQ(cloud.point_step, 24u);
}
