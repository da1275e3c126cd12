// FastSLAM 2.0: on the synthetic globe with perfect association (pose and
// map error bounds, covariances PSD, bad input leaves the state unchanged),
// and on a linear-Gaussian toy (no rotation noise, so z = m - p is linear)
// where many particles must reproduce the Kalman filter's posterior within
// their sampling error.
#include "bad_frames.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "globe_run.hpp"
#include "hapi_eskf/fastslam/fastslam2.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <set>

namespace hapi_eskf {
namespace {

using fastslam::FastSlam2;
using fastslam::FastSlamSettings;

TEST(FastSlam2, OnlineOnGlobeWithinBounds) {
  const sim::GlobeRun run = sim::makeGlobeRun(7, 1500, 80, 1.0);
  FastSlamSettings s;
  s.num_particles = 50;
  FastSlam2 slam(s);
  ASSERT_EQ(slam.reset(run.truth[0], 0.0), Status::kOk);
  std::set<uint64_t> known;
  double max_pos = 0, max_rot = 0;
  bool psd = true;
  int resampled = 0;
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    fastslam::FastSlamReport rep;
    ASSERT_EQ(slam.processFrame(sim::associateByTruth(run.frames[k], 20, &known), &rep), Status::kOk) << k;
    resampled += rep.resampled;
    const auto e = sim::poseError(run.truth[k], slam.pose());
    max_pos = std::max(max_pos, e.head<3>().norm());
    max_rot = std::max(max_rot, e.tail<3>().norm());
    psd = psd && sim::isPsd(slam.poseCovariance());
  }
  std::vector<Vec3> pts;
  for (const LandmarkInfo& l : slam.landmarks()) {
    pts.push_back(l.position);
    psd = psd && sim::isPsd(l.covariance);
  }
  const double map_rms = sim::sphereRms(run.globe, pts);
  std::printf("fastslam2 globe: max pos err %.4f m, max rot err %.4f rad, map rms %.4f m (%zu landmarks), "
              "resampled %d of %zu frames\n",
              max_pos, max_rot, map_rms, pts.size(), resampled, run.frames.size());
  EXPECT_LT(max_pos, 0.03);
  EXPECT_LT(max_rot, 0.01);
  EXPECT_LT(map_rms, 0.004);
  EXPECT_TRUE(psd);
  EXPECT_GT(resampled, 0);
}

TEST(FastSlam2, BadInputLeavesStateUnchanged) {
  const sim::GlobeRun run = sim::makeGlobeRun(8, 800, 12, 0.1);
  FastSlamSettings s;
  s.num_particles = 20;
  FastSlam2 slam(s);
  ASSERT_EQ(slam.reset(run.truth[0], 0.0), Status::kOk);
  std::set<uint64_t> known;
  for (int k = 0; k < 10; ++k) ASSERT_EQ(slam.processFrame(sim::associateByTruth(run.frames[k], 20, &known)), Status::kOk);
  std::set<uint64_t> probe = known;
  const AssociatedFrame good = sim::associateByTruth(run.frames[10], 20, &probe);
  ASSERT_GE(good.measurements.size(), 2u);
  ASSERT_FALSE(good.measurements[0].is_new);
  const std::vector<fastslam::Particle> before = slam.particles();
  const int n0 = slam.numLandmarks();
  for (const sim::BadFrame& b : sim::badFrames(good, 0.05)) {
    EXPECT_EQ(slam.processFrame(b.frame), b.expected) << b.what;
    ASSERT_EQ(slam.numLandmarks(), n0) << b.what;
    const auto& now = slam.particles();
    ASSERT_EQ(now.size(), before.size());
    for (std::size_t i = 0; i < now.size(); ++i) {
      EXPECT_EQ(now[i].p, before[i].p) << b.what;
      EXPECT_EQ(now[i].q.coeffs(), before[i].q.coeffs()) << b.what;
      EXPECT_EQ(now[i].log_weight, before[i].log_weight) << b.what;
      EXPECT_EQ(now[i].map, before[i].map) << b.what;  // the very same landmark EKFs
    }
  }
  EXPECT_EQ(slam.processFrame(good), Status::kOk);
}

// Linear-Gaussian toy: orientation fixed (no rotation noise), so the
// measurement z = m - p is linear and FastSLAM's motion prior (constant
// velocity from the particle's last step, velocity random walk) is the
// linear model p' = 2 p - p_prev + n, n ~ N(0, sigma^2 dt^3 / 3 I). The
// Kalman filter over [p, p_prev, m_1..m_L] is then the exact posterior.
TEST(FastSlam2, ManyParticlesMatchTheKalmanFilterOnALinearGaussianToy) {
  const int L = 5, frames = 12, N = 4000;
  const double dt = 0.1, sigma_a = 0.5;
  const double q = sigma_a * sigma_a * dt * dt * dt / 3.0;
  std::mt19937 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto randn3 = [&] { return drawVec3(n01, rng); };
  std::vector<Vec3> m(L);
  for (int j = 0; j < L; ++j) m[j] = Vec3(0.3 * j - 0.6, 0.2 * (j % 2) - 0.1, 1.0 + 0.1 * j);
  std::vector<Mat3> Cz(L);
  for (int j = 0; j < L; ++j) {
    const Mat3 A = Mat3::Random();
    Cz[j] = 1e-5 * (A * A.transpose() + 0.5 * Mat3::Identity());
  }

  FastSlamSettings s;
  s.num_particles = N;
  s.sigma_acceleration = sigma_a;
  s.sigma_angular_acceleration = 0.0;
  s.resample_threshold = 0.5;
  FastSlam2 fs(s);
  ASSERT_EQ(fs.reset(PoseState(), 0.0), Status::kOk);

  // KF state [p, p_prev, m_1..m_L], all exactly 0 / unknown at the start.
  const int D = 6 + 3 * L;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(D);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(D, D);
  Vec3 p_true = Vec3::Zero(), p_prev_true = Vec3::Zero();
  double worst_pose = 0, worst_map = 0, worst_cov = 0;
  for (int k = 0; k < frames; ++k) {
    if (k > 0) {
      const Vec3 next = 2.0 * p_true - p_prev_true + std::sqrt(q) * randn3();
      p_prev_true = p_true;
      p_true = next;
      // Predict: p' = 2 p - p_prev + n, p_prev' = p.
      Eigen::MatrixXd F = Eigen::MatrixXd::Identity(D, D);
      F.block<3, 3>(0, 0) = 2.0 * Mat3::Identity();
      F.block<3, 3>(0, 3) = -Mat3::Identity();
      F.block<3, 3>(3, 0) = Mat3::Identity();
      F.block<3, 3>(3, 3) = Mat3::Zero();
      x = F * x;
      P = F * P * F.transpose();
      P.block<3, 3>(0, 0) += q * Mat3::Identity();
    }
    AssociatedFrame f;
    f.stamp = k * dt;
    std::vector<Vec3> z(L);
    for (int j = 0; j < L; ++j) {
      z[j] = m[j] - p_true + Cz[j].llt().matrixL() * randn3();
      AssociatedMeasurement am;
      am.landmark_id = j + 1;
      am.is_new = k == 0;
      am.z = z[j];
      am.Cz = Cz[j];
      f.measurements.push_back(am);
    }
    ASSERT_EQ(fs.processFrame(f), Status::kOk);
    if (k == 0) {
      // New landmarks m = p + z (P has only zeros at the start: exact pose).
      for (int j = 0; j < L; ++j) {
        x.segment<3>(6 + 3 * j) = x.head<3>() + z[j];
        P.block<3, 3>(6 + 3 * j, 6 + 3 * j) = Cz[j];
      }
    } else {
      Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * L, D), R = Eigen::MatrixXd::Zero(3 * L, 3 * L);
      Eigen::VectorXd r(3 * L);
      for (int j = 0; j < L; ++j) {
        H.block<3, 3>(3 * j, 0) = -Mat3::Identity();
        H.block<3, 3>(3 * j, 6 + 3 * j) = Mat3::Identity();
        R.block<3, 3>(3 * j, 3 * j) = Cz[j];
        r.segment<3>(3 * j) = z[j] - (x.segment<3>(6 + 3 * j) - x.head<3>());
      }
      const Eigen::MatrixXd S = H * P * H.transpose() + R;
      const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
      x += K * r;
      P = (Eigen::MatrixXd::Identity(D, D) - K * H) * P;
      P = 0.5 * (P + P.transpose());
    }
    if (k == 0) continue;
    // Sampling error of a weighted mean of N particles: sigma^2 / N_eff,
    // N_eff >= resample_threshold N between resamplings; allow 4 sigma per
    // axis of the KF's own covariance (chi^2(3) < 4^2 * 3 ~ 48 over the
    // frames and landmarks compared).
    const double n_eff_min = s.resample_threshold * N;
    const Vec3 dp = fs.pose().p - x.head<3>();
    const Mat3 Ppp = P.block<3, 3>(0, 0);
    worst_pose = std::max(worst_pose, std::sqrt(dp.dot(Ppp.ldlt().solve(dp)) * n_eff_min / 3.0));
    const auto lm = fs.landmarks();
    for (int j = 0; j < L; ++j) {
      const Vec3 dm = lm[j].position - x.segment<3>(6 + 3 * j);
      const Mat3 Pmm = P.block<3, 3>(6 + 3 * j, 6 + 3 * j);
      worst_map = std::max(worst_map, std::sqrt(dm.dot(Pmm.ldlt().solve(dm)) * n_eff_min / 3.0));
    }
    // The spread's covariance against the KF's: relative error of each
    // variance along the KF's axes (sampling error ~ sqrt(2 / N_eff)).
    const Eigen::SelfAdjointEigenSolver<Mat3> es(Ppp);
    const Mat3 C = fs.poseCovariance().topLeftCorner<3, 3>();
    for (int a = 0; a < 3; ++a) {
      const Vec3 u = es.eigenvectors().col(a);
      worst_cov = std::max(worst_cov, std::abs(u.dot(C * u) / u.dot(Ppp * u) - 1.0));
    }
  }
  std::printf("fastslam vs KF (%d particles): worst pose mean %.2f, landmark mean %.2f sampling sigmas; "
              "worst relative pose variance error %.3f\n",
              N, worst_pose, worst_map, worst_cov);
  EXPECT_LT(worst_pose, 4.0);
  EXPECT_LT(worst_map, 4.0);
  EXPECT_LT(worst_cov, 0.2);
}

}  // namespace
}  // namespace hapi_eskf
