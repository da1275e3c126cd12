// graph::marginalCovariances (Schur complement on the poses) against
// ceres::Covariance (sparse QR of the whole problem) on a small bundle with
// a fixed gauge pose, free poses on the quaternion manifold, a pose prior and
// a robust loss that has some residuals beyond its quadratic part: the same
// blocks up to round-off. Also the dense inverse it uses
// (cpu_la::inverseSymmetric), OpenBLAS's and Eigen's.
#include "hapi_eskf/graph/marginal_covariance.hpp"

#include "../src/covariance/cpu_linear_algebra.hpp"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include <random>

namespace hapi_eskf {
namespace {

// r = (z - R^T (m - p)) / sigma, pose = [p, q (x y z w)].
struct PointInCamera {
  PointInCamera(const Vec3& z, double sigma) : z_(z), sigma_(sigma) {}
  template <typename T>
  bool operator()(const T* pose, const T* m, T* r) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(pose), x(m);
    Eigen::Map<const Eigen::Quaternion<T>> q(pose + 3);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> residual(r);
    residual = (z_.cast<T>() - q.conjugate() * (x - p)) / T(sigma_);
    return true;
  }
  Vec3 z_;
  double sigma_;
};

// r = (pose - pose0) / sigma over all 7 numbers (a prior that holds a pose).
struct PosePrior {
  PosePrior(const Eigen::Matrix<double, 7, 1>& x0, double sigma) : x0_(x0), sigma_(sigma) {}
  template <typename T>
  bool operator()(const T* pose, T* r) const {
    for (int i = 0; i < 7; ++i) r[i] = (pose[i] - T(x0_[i])) / T(sigma_);
    return true;
  }
  Eigen::Matrix<double, 7, 1> x0_;
  double sigma_;
};

// Two points tied together (the Schur form does not apply).
struct PointToPoint {
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = a[i] - b[i];
    return true;
  }
};

using Pose = Eigen::Matrix<double, 7, 1>;

struct Bundle {
  std::vector<Pose> poses;
  std::vector<Vec3> points;
  ceres::Problem problem;
};

// Pose 0 fixed (gauge), poses 1..4 free, pose 1 also under a prior; every
// point seen by 2-3 poses with noise; Huber at 1 sigma so some residuals are
// in its linear part.
void makeBundle(Bundle* b) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int k = 0; k < 5; ++k) {
    Pose x;
    x.head<3>() = Vec3(0.1 * k, 0.02 * k, 0.0);
    x.tail<4>() = Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * k, Vec3::UnitY())).coeffs();
    b->poses.push_back(x);
  }
  for (int i = 0; i < 30; ++i) b->points.emplace_back(0.05 * (i % 6) - 0.1, 0.04 * (i / 6) - 0.1, 1.0 + 0.01 * i);
  const double sigma = 0.002;
  for (int i = 0; i < 30; ++i)
    for (int k = i % 3; k < 5; k += 2) {
      const Pose& x = b->poses[k];
      const Eigen::Quaterniond q(x.tail<4>().data());
      const Vec3 z = q.conjugate() * (b->points[i] - x.head<3>()) + sigma * Vec3(noise(rng), noise(rng), noise(rng));
      b->problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointInCamera, 3, 7, 3>(new PointInCamera(z, sigma)),
                                  new ceres::HuberLoss(1.0), b->poses[k].data(), b->points[i].data());
    }
  for (int i = 0; i < 30; ++i) b->points[i] += 0.003 * Vec3(noise(rng), noise(rng), noise(rng));  // off the optimum
  for (Pose& x : b->poses)
    b->problem.SetManifold(x.data(), new ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::EigenQuaternionManifold>(
                                         ceres::EuclideanManifold<3>(), ceres::EigenQuaternionManifold()));
  b->problem.SetParameterBlockConstant(b->poses[0].data());
  b->problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PosePrior, 7, 7>(new PosePrior(b->poses[1], 0.01)), nullptr,
                              b->poses[1].data());
}

// Every point and the free poses 1..4.
void freeBlocks(Bundle* b, std::vector<double*>* points, std::vector<double*>* poses) {
  for (Vec3& m : b->points) points->push_back(m.data());
  for (std::size_t k = 1; k < b->poses.size(); ++k) poses->push_back(b->poses[k].data());
}

TEST(MarginalCovariance, EqualsCeresCovariance) {
  Bundle b;
  makeBundle(&b);
  std::vector<double*> points, poses;
  freeBlocks(&b, &points, &poses);
  std::vector<Mat3> point_cov;
  std::vector<Mat6> pose_cov;
  ASSERT_TRUE(graph::marginalCovariances(&b.problem, points, poses, &point_cov, &pose_cov));
  ASSERT_EQ(point_cov.size(), points.size());
  ASSERT_EQ(pose_cov.size(), poses.size());

  ceres::Covariance::Options opt;
  opt.algorithm_type = ceres::SPARSE_QR;
  ceres::Covariance reference(opt);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (double* m : points) blocks.emplace_back(m, m);
  for (double* x : poses) blocks.emplace_back(x, x);
  ASSERT_TRUE(reference.Compute(blocks, &b.problem));
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> C;
    reference.GetCovarianceBlock(points[i], points[i], C.data());
    EXPECT_LT((point_cov[i] - C).norm(), 1e-9 * C.norm()) << "point " << i;
  }
  for (std::size_t k = 0; k < poses.size(); ++k) {
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> C;
    reference.GetCovarianceBlockInTangentSpace(poses[k], poses[k], C.data());
    EXPECT_LT((pose_cov[k] - C).norm(), 1e-9 * C.norm()) << "pose " << k + 1;
  }
}

TEST(MarginalCovariance, RefusesAResidualBetweenTwoPoints) {
  Bundle b;
  makeBundle(&b);
  b.problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointToPoint, 3, 3, 3>(new PointToPoint), nullptr,
                             b.points[0].data(), b.points[1].data());
  std::vector<double*> points, poses;
  freeBlocks(&b, &points, &poses);
  std::vector<Mat3> point_cov;
  std::vector<Mat6> pose_cov;
  EXPECT_FALSE(graph::marginalCovariances(&b.problem, points, poses, &point_cov, &pose_cov));
}

TEST(MarginalCovariance, RefusesAnUndeterminedPose) {
  Bundle b;
  makeBundle(&b);
  // A free pose that no residual sees: no information, S is singular.
  Pose unseen = b.poses[2];
  b.problem.AddParameterBlock(unseen.data(), 7,
                              new ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::EigenQuaternionManifold>(
                                  ceres::EuclideanManifold<3>(), ceres::EigenQuaternionManifold()));
  std::vector<double*> points, poses;
  freeBlocks(&b, &points, &poses);
  poses.push_back(unseen.data());
  std::vector<Mat3> point_cov;
  std::vector<Mat6> pose_cov;
  EXPECT_FALSE(graph::marginalCovariances(&b.problem, points, poses, &point_cov, &pose_cov));
}

TEST(MarginalCovariance, InverseSymmetricOnEitherPath) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(60, 60);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = g(rng);
  const Eigen::MatrixXd S = A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(60, 60);
  for (CpuLinearAlgebra la : {CpuLinearAlgebra::kBlas, CpuLinearAlgebra::kEigen}) {
    Eigen::MatrixXd X = S;
    ASSERT_TRUE(cpu_la::inverseSymmetric(la, &X));
    EXPECT_LT((X * S - Eigen::MatrixXd::Identity(60, 60)).norm(), 1e-8);
    EXPECT_EQ(X, X.transpose());
    Eigen::MatrixXd N = -S;
    EXPECT_FALSE(cpu_la::inverseSymmetric(la, &N));
  }
}

}  // namespace
}  // namespace hapi_eskf
