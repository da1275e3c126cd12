// Geometric consistency of descriptor candidates (association.cpp,
// EskfSettings::ransac_iterations): wrong matches that the per-candidate
// Mahalanobis gate accepts when the predicted pose is uncertain are rejected
// by the RANSAC rigid fit, correct ones are kept.
#include "basic_settings.hpp"
#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/so3.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace hapi_eskf;

namespace {

// n landmark/measurement pairs seen from camera pose (R, t); the pairs listed
// in `wrong` get a measurement of another point 3 cm away.
void makePairs(int n, const std::vector<int>& wrong, std::vector<Vec3>* X, std::vector<Vec3>* Z,
               std::vector<Mat3>* W, std::vector<Mat3>* Cz, Mat3* R, Vec3* t) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  *R = Eigen::AngleAxisd(0.3, Vec3(0.2, 1.0, -0.1).normalized()).toRotationMatrix();
  *t = Vec3(0.1, -0.2, 0.05);
  const double s_m = 1e-3, s_z = 5e-4;
  for (int i = 0; i < n; ++i) {
    const Vec3 zc(0.3 * g(rng), 0.2 * g(rng), 0.5 + 0.1 * std::abs(g(rng)));
    Vec3 x = *R * zc + *t;
    X->push_back(x + s_m * drawVec3(g, rng));
    Z->push_back(zc + s_z * drawVec3(g, rng));
    W->push_back(s_m * s_m * Mat3::Identity());
    Cz->push_back(s_z * s_z * Mat3::Identity());
  }
  for (int i : wrong) (*Z)[i] += Vec3(0.03, -0.01, 0.0);
}

}  // namespace

TEST(Ransac, RejectsWrongMatchesKeepsCorrect) {
  std::vector<Vec3> X, Z;
  std::vector<Mat3> W, Cz;
  Mat3 R;
  Vec3 t;
  const std::vector<int> wrong{2, 5, 11, 17, 23, 29};  // 20 % outliers
  makePairs(30, wrong, &X, &Z, &W, &Cz, &R, &t);
  const std::vector<char> inl = ransacRigidInliers(X, Z, W, Cz, 200, 11.345);
  ASSERT_EQ(inl.size(), X.size());
  int kept_good = 0;
  for (int i = 0; i < 30; ++i) {
    const bool is_wrong = std::find(wrong.begin(), wrong.end(), i) != wrong.end();
    if (is_wrong) EXPECT_FALSE(inl[i]) << i;
    else kept_good += inl[i];
  }
  // chi^2(3) at 99 %: about 1 % of the correct pairs may fall outside.
  EXPECT_GE(kept_good, 22);
}

TEST(Ransac, UndecidedWithoutSupportAndDeterministic) {
  std::vector<Vec3> X, Z;
  std::vector<Mat3> W, Cz;
  Mat3 R;
  Vec3 t;
  makePairs(12, {}, &X, &Z, &W, &Cz, &R, &t);
  EXPECT_EQ(ransacRigidInliers(X, Z, W, Cz, 100, 11.345), ransacRigidInliers(X, Z, W, Cz, 100, 11.345));
  // Every measurement paired with a random landmark: no rigid fit explains 3.
  std::vector<Vec3> Xs = X;
  std::mt19937 rng(3);
  for (auto& x : Xs) x = Vec3(std::uniform_real_distribution<double>(-5, 5)(rng), 0.0, 0.0) + x * 10.0;
  EXPECT_TRUE(ransacRigidInliers(Xs, Z, W, Cz, 100, 11.345).empty());
  EXPECT_TRUE(ransacRigidInliers({X[0], X[1]}, {Z[0], Z[1]}, {W[0], W[1]}, {Cz[0], Cz[1]}, 100, 11.345).empty());
}

TEST(Ransac, SettingsValidated) {
  EskfSettings s;
  s.ransac_iterations = -1;
  EXPECT_NE(s.validate().find("ransac_iterations"), std::string::npos);
  s = EskfSettings();
  s.measurement_angular_sigma = -1e-3;
  EXPECT_NE(s.validate().find("measurement_angular_sigma"), std::string::npos);
  s.measurement_angular_sigma = 1e-3;
  s.ransac_iterations = 200;
  EXPECT_EQ(s.validate(), "");
}

// EskfSettings::measurement_angular_sigma: a new landmark's covariance is the
// stereo C_z plus (sigma |z|)^2 across the ray, nothing along it.
TEST(MeasurementModel, RedetectionNoiseAddedAcrossTheRay) {
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 10;
  s.initial_sigma_position = 1e-9;
  s.initial_sigma_orientation = 1e-9;
  s.measurement_angular_sigma = 2e-3;
  s.max_new_landmarks = 5;
  s.max_update_landmarks = 10;
  ASSERT_EQ(s.validate(), "");
  Eskf f(s, makeCpuBackend(s.max_landmarks, 4));
  ASSERT_EQ(f.reset(PoseState(), 1.0), Status::kOk);  // no prediction before the frame
  StereoFrame fr;
  fr.stamp = 1.0;
  fr.descriptor_length = 4;
  fr.descriptors = {1, 2, 3, 4};
  StereoMeasurement m;
  m.z = Vec3(0.1, -0.2, 0.6);
  m.Cz = Vec3(1e-8, 2e-8, 4e-6).asDiagonal();
  fr.measurements.push_back(m);
  ASSERT_EQ(f.processFrame(fr), Status::kOk);
  ASSERT_EQ(f.numLandmarks(), 1);
  const Mat3 C = f.landmarks()[0].covariance;
  const Vec3 r = m.z.normalized();
  const Mat3 expected = m.Cz + 4e-6 * m.z.squaredNorm() * (Mat3::Identity() - r * r.transpose());
  EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(r.dot((C - m.Cz) * r), 0.0, 1e-14);
}

// EskfSettings::bootstrap_landmarks: the frame that finds the pool empty adds
// up to that many landmarks, later frames at most max_new_landmarks.
TEST(Bootstrap, EmptyPoolFrameAddsBootstrapCount) {
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 300;
  s.max_new_landmarks = 10;
  s.max_update_landmarks = 50;
  s.bootstrap_landmarks = 40;
  ASSERT_EQ(s.validate(), "");
  Eskf f(s, makeCpuBackend(s.max_landmarks, 4));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(11);
  auto frame = [&](double stamp) {
    StereoFrame fr;
    fr.stamp = stamp;
    fr.descriptor_length = 4;
    for (int i = 0; i < 60; ++i) {
      StereoMeasurement m;
      m.z = Vec3(0.01 * (i % 10) - 0.05, 0.01 * (i / 10) - 0.03, 0.5 + 0.001 * i);
      m.Cz = 1e-6 * Mat3::Identity();
      m.frontend_id = static_cast<uint32_t>(i);
      m.response = static_cast<float>(i);
      fr.measurements.push_back(m);
      for (int b = 0; b < 4; ++b) fr.descriptors.push_back(static_cast<uint8_t>(rng()));  // all distinct
    }
    return fr;
  };
  IterationReport rep;
  ASSERT_EQ(f.processFrame(frame(0.1), &rep), Status::kOk);
  EXPECT_EQ(rep.n_added, 40);
  ASSERT_EQ(f.processFrame(frame(0.2), &rep), Status::kOk);
  EXPECT_LE(rep.n_added, 10);
  s.bootstrap_landmarks = s.max_landmarks + 1;
  EXPECT_NE(s.validate().find("bootstrap_landmarks"), std::string::npos);
}

// Filter level: after a long prediction the per-candidate gate is loose, so
// matches 2 cm off (a different physical point with the same descriptor, as
// ORB finds on repetitive texture) pass it. The RANSAC step rejects them and
// the pose stays at the truth; without it the update is pulled off.
namespace {
struct WrongMatchResult {
  IterationReport rep;
  double pos_err = 0, rot_err = 0;
};

WrongMatchResult runWrongMatches(int ransac_iterations, double initial_sigma = 1e-6, double offset = 0.02) {
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 100;
  s.max_new_landmarks = 50;
  s.max_update_landmarks = 50;
  s.initial_sigma_position = initial_sigma;
  s.initial_sigma_orientation = initial_sigma;
  s.initial_sigma_velocity = 0.5;
  s.initial_sigma_angular_velocity = 0.5;
  s.ransac_iterations = ransac_iterations;
  EXPECT_EQ(s.validate(), "");
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  EXPECT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const int n = 36;
  std::vector<Vec3> pts;
  std::vector<uint8_t> desc;
  for (int i = 0; i < n; ++i) {
    pts.emplace_back(0.3 * u(rng), 0.2 * u(rng), 0.6 + 0.2 * u(rng));
    for (int b = 0; b < 32; ++b) desc.push_back(static_cast<uint8_t>(rng()));
  }
  // Stereo-like covariance: 0.3 mm across the ray, 2 mm along it.
  auto cov = [](const Vec3& z) {
    const Vec3 r = z.normalized();
    return Mat3(9e-8 * Mat3::Identity() + (4e-6 - 9e-8) * r * r.transpose());
  };
  auto frame = [&](double stamp, bool wrong) {
    StereoFrame fr;
    fr.stamp = stamp;
    fr.descriptor_length = 32;
    fr.descriptors = desc;
    for (int i = 0; i < n; ++i) {
      StereoMeasurement m;
      m.Cz = cov(pts[i]);
      m.z = pts[i] + Mat3(m.Cz.llt().matrixL()) * drawVec3(g, rng);
      if (wrong && i % 6 == 0) m.z += offset * drawVec3(u, rng).normalized();
      m.frontend_id = static_cast<uint32_t>(i);
      m.response = 1.0f;
      fr.measurements.push_back(m);
    }
    return fr;
  };
  WrongMatchResult r;
  EXPECT_EQ(f.processFrame(frame(0.0, false), &r.rep), Status::kOk);
  EXPECT_EQ(r.rep.n_added, n);
  EXPECT_EQ(f.processFrame(frame(0.3, true), &r.rep), Status::kOk);  // the camera did not move
  // Relative to the first frame's pose (the landmarks were made from it).
  const auto e = sim::poseError(PoseState(), f.pose());
  r.pos_err = e.head<3>().norm();
  r.rot_err = e.tail<3>().norm();
  return r;
}
}  // namespace

TEST(Ransac, FilterRejectsWrongMatchesThatPassTheGate) {
  const WrongMatchResult off = runWrongMatches(0), on = runWrongMatches(200);
  std::printf("without RANSAC: updated %d gated %d |dp| %.2e m |dth| %.2e rad; with: updated %d gated %d (ransac) "
              "|dp| %.2e m |dth| %.2e rad\n",
              off.rep.n_updated, off.rep.n_gated_out, off.pos_err, off.rot_err, on.rep.n_updated, on.rep.n_gated_out,
              on.pos_err, on.rot_err);
  // The gate alone lets all 6 wrong matches through ...
  EXPECT_EQ(off.rep.n_updated, 36);
  // ... RANSAC removes them (and at most one correct pair at chi^2 99 %).
  EXPECT_GE(on.rep.n_gated_out, 6);
  EXPECT_GE(on.rep.n_updated, 29);
  EXPECT_LT(on.pos_err, 0.5 * off.pos_err);
  EXPECT_LT(on.pos_err, 1e-3);
}

// The same with a map whose landmarks share a large uncertainty (made from a
// pose known to 2 cm / 20 mrad, as after a start while moving): their
// marginals are cm-wide, but the rigid fit absorbs what they share, so
// matches 8 mm off must still be found by each point's own noise.
TEST(Ransac, RejectsWrongMatchesWhenTheWholeMapIsUncertain) {
  const WrongMatchResult r = runWrongMatches(200, 0.02, 0.008);
  EXPECT_GE(r.rep.n_gated_out, 6);
  EXPECT_GE(r.rep.n_updated, 29);
  EXPECT_LT(r.rep.mean_nis, 4.5);  // chi^2(3) per landmark: mean 3; one wrong match alone adds ~20
}
