// Two-step MMSE triangulation: exactness without noise, and covariance
// consistency (NEES Monte Carlo) with Gaussian pixel noise.
#include "hapi_frontend/mmse_triangulator.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <random>

using namespace hapi_frontend;

namespace {
struct StereoSetup {
  Eigen::Matrix3d Kl, Kr;
  StereoRig rig;
  StereoSetup() {
    Kl << 502.3, 0, 321.4, 0, 501.8, 238.7, 0, 0, 1;
    Kr << 501.6, 0, 318.9, 0, 501.1, 240.2, 0, 0, 1;
    rig.R_lr = Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
    rig.t_lr = Eigen::Vector3d(0.06, 0.001, -0.002);
  }
  Eigen::Vector2d projL(const Eigen::Vector3d& X) const {
    const Eigen::Vector3d q = Kl * X;
    return q.head<2>() / q.z();
  }
  Eigen::Vector2d projR(const Eigen::Vector3d& X) const {
    const Eigen::Vector3d q = Kr * (rig.R_lr.transpose() * (X - rig.t_lr));
    return q.head<2>() / q.z();
  }
};
}  // namespace

TEST(Mmse, NoiseFreeIsExact) {
  StereoSetup s;
  MmseTriangulator tri(s.Kl, s.Kr, s.rig, 0.5);
  for (const Eigen::Vector3d X : {Eigen::Vector3d(0.1, -0.05, 0.4), Eigen::Vector3d(-0.3, 0.2, 2.0),
                                  Eigen::Vector3d(0.0, 0.0, 8.0)}) {
    const MmseEstimate e = tri.estimate(s.projL(X), s.projR(X));
    ASSERT_TRUE(e.valid);
    // The weak depth prior (sigma = 10 z0) biases by < 1e-5 relative.
    EXPECT_LT((e.position - X).norm(), 1e-5 * X.norm());
    // Symmetric positive definite, depth variance dominates.
    EXPECT_TRUE(e.covariance.isApprox(e.covariance.transpose(), 1e-12));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(e.covariance);
    EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
    EXPECT_GT(e.covariance(2, 2), e.covariance(0, 0));
  }
}

TEST(Mmse, RejectsPointsBehindTheCameras) {
  StereoSetup s;
  MmseTriangulator tri(s.Kl, s.Kr, s.rig, 0.5);
  const Eigen::Vector3d X(0.1, 0.0, 1.0);
  Eigen::Vector2d ur = s.projR(X);
  ur.x() += 60.0;  // negative disparity: rays meet behind the rig
  EXPECT_FALSE(tri.estimate(s.projL(X), ur).valid);
  EXPECT_FALSE(tri.estimate(s.projL(X), s.projR(X), 0.0, 1.0).valid);
}

// NEES of the estimate with iid N(0, sigma^2) pixel noise must average 3
// (3 dof) and the covariance must match the sample covariance of the errors.
TEST(Mmse, NeesMonteCarloConsistent) {
  StereoSetup s;
  const double sigma = 0.5;
  MmseTriangulator tri(s.Kl, s.Kr, s.rig, sigma);
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (const Eigen::Vector3d X : {Eigen::Vector3d(0.05, 0.02, 0.5), Eigen::Vector3d(-0.4, 0.3, 3.0)}) {
    const int N = 4000;
    double nees = 0;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d Cmean = Eigen::Matrix3d::Zero();
    for (int i = 0; i < N; ++i) {
      const Eigen::Vector2d ul = s.projL(X) + sigma * Eigen::Vector2d(n01(rng), n01(rng));
      const Eigen::Vector2d ur = s.projR(X) + sigma * Eigen::Vector2d(n01(rng), n01(rng));
      const MmseEstimate e = tri.estimate(ul, ur);
      ASSERT_TRUE(e.valid);
      const Eigen::Vector3d d = e.position - X;
      nees += d.dot(e.covariance.ldlt().solve(d));
      scatter += d * d.transpose();
      Cmean += e.covariance;
    }
    nees /= N;
    // Mean of N chi2(3) has std sqrt(6/N) = 0.04.
    EXPECT_NEAR(nees, 3.0, 0.15) << "X = " << X.transpose();
    scatter /= N;
    Cmean /= N;
    EXPECT_NEAR(scatter(2, 2) / Cmean(2, 2), 1.0, 0.1);
    EXPECT_NEAR(scatter(0, 0) / Cmean(0, 0), 1.0, 0.1);
  }
}

// A wrong sigma must be caught by the same statistic (the test can fail).
TEST(Mmse, NeesDetectsMisstatedNoise) {
  StereoSetup s;
  MmseTriangulator tri(s.Kl, s.Kr, s.rig, 0.25);  // claims half the true noise
  std::mt19937 rng(9);
  std::normal_distribution<double> n01(0.0, 0.5);
  const Eigen::Vector3d X(0.1, -0.1, 1.0);
  double nees = 0;
  const int N = 2000;
  for (int i = 0; i < N; ++i) {
    const MmseEstimate e = tri.estimate(s.projL(X) + Eigen::Vector2d(n01(rng), n01(rng)),
                                        s.projR(X) + Eigen::Vector2d(n01(rng), n01(rng)));
    const Eigen::Vector3d d = e.position - X;
    nees += d.dot(e.covariance.ldlt().solve(d));
  }
  EXPECT_GT(nees / N, 10.0);
}
