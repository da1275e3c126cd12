// fitAffineFlow on synthetic displacements: exact data, outliers, too few or
// collinear points, and the covariance against the error with known noise.
#include "hapi_frontend/affine_flow_fit.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

namespace hapi_frontend {
namespace {

using Affine = Eigen::Matrix<double, 6, 1>;

Eigen::Vector2d flowAt(const Affine& a, const Eigen::Vector2d& x, const Eigen::Vector2d& c) {
  const Eigen::Vector2d r = x - c;
  return Eigen::Vector2d(a(0) + a(2) * r.x() + a(3) * r.y(), a(1) + a(4) * r.x() + a(5) * r.y());
}

struct Data {
  std::vector<Eigen::Vector2d> from, d;
};

Data makeData(const Affine& a, const Eigen::Vector2d& c, int n, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> pos(-40, 40);
  std::normal_distribution<double> e(0, noise);
  Data data;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d x = c + Eigen::Vector2d(pos(rng), pos(rng));
    data.from.push_back(x);
    data.d.push_back(flowAt(a, x, c) + Eigen::Vector2d(e(rng), e(rng)));
  }
  return data;
}

const Eigen::Vector2d kCentre(320, 240);

TEST(AffineFlowFit, ExactDataGivesTheParametersAndTheFloor) {
  std::mt19937 rng(1);
  Affine a;
  a << 1.5, -0.25, 0.01, -0.02, 0.03, 0.005;
  const Data data = makeData(a, kCentre, 30, 0.0, rng);
  const AffineFlowFit fit = fitAffineFlow(data.from, data.d, kCentre, AffineFitSettings());
  ASSERT_TRUE(fit.ok);
  EXPECT_LT((fit.affine - a).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(fit.inliers, 30);
  EXPECT_DOUBLE_EQ(fit.sigma, AffineFitSettings().min_sigma);
  // u and v components are fitted separately: no cross covariance.
  EXPECT_DOUBLE_EQ(fit.covariance(0, 1), 0.0);
  EXPECT_GT(fit.covariance(0, 0), 0.0);
  EXPECT_TRUE(fit.covariance.isApprox(fit.covariance.transpose()));
}

TEST(AffineFlowFit, OutliersAreRejected) {
  std::mt19937 rng(2);
  Affine a;
  a << -0.7, 2.1, 0.0, 0.01, -0.01, 0.0;
  Data data = makeData(a, kCentre, 60, 0.05, rng);
  // A third of the tracks wrong by 1-5 px.
  std::uniform_real_distribution<double> wrong(1.0, 5.0);
  for (int i = 0; i < 20; ++i) data.d[3 * i] += Eigen::Vector2d(wrong(rng), -wrong(rng));
  const AffineFlowFit fit = fitAffineFlow(data.from, data.d, kCentre, AffineFitSettings());
  ASSERT_TRUE(fit.ok);
  EXPECT_EQ(fit.inliers, 40);
  for (int i = 0; i < 60; ++i) EXPECT_EQ(fit.inlier[i], i % 3 != 0 || i >= 60) << i;
  EXPECT_NEAR(fit.affine(0), a(0), 0.05);
  EXPECT_NEAR(fit.affine(1), a(1), 0.05);
  EXPECT_NEAR(fit.sigma, 0.05, 0.015);
}

TEST(AffineFlowFit, TooFewOrCollinearPointsFail) {
  std::mt19937 rng(3);
  const Affine a = Affine::Zero();
  const Data few = makeData(a, kCentre, 9, 0.01, rng);
  EXPECT_FALSE(fitAffineFlow(few.from, few.d, kCentre, AffineFitSettings()).ok);
  Data line;
  for (int i = 0; i < 30; ++i) {
    line.from.emplace_back(300 + i, 200 + 2 * i);
    line.d.emplace_back(0.5, 0.5);
  }
  EXPECT_FALSE(fitAffineFlow(line.from, line.d, kCentre, AffineFitSettings()).ok);
  Data bad = makeData(a, kCentre, 30, 0.01, rng);
  bad.d[4].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fitAffineFlow(bad.from, bad.d, kCentre, AffineFitSettings()).ok);
}

TEST(AffineFlowFit, CovarianceMatchesTheErrorWithKnownNoise) {
  std::mt19937 rng(4);
  Affine a;
  a << 0.3, -0.2, 0.01, 0.0, -0.01, 0.02;
  double nees = 0;
  const int trials = 400;
  for (int k = 0; k < trials; ++k) {
    const Data data = makeData(a, kCentre, 40, 0.1, rng);
    const AffineFlowFit fit = fitAffineFlow(data.from, data.d, kCentre, AffineFitSettings());
    ASSERT_TRUE(fit.ok);
    const Affine e = fit.affine - a;
    nees += e.dot(fit.covariance.ldlt().solve(e));
  }
  nees /= trials;
  // Mean of 400 chi-square(6) samples: 6 +- 0.24 (1 sigma); the estimated
  // sigma and the few Gaussian tails rejected as outliers widen it a little.
  EXPECT_NEAR(nees, 6.0, 0.8);
}

}  // namespace
}  // namespace hapi_frontend
