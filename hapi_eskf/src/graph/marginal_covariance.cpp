// Marginal covariances through the Schur complement on the poses
// (marginal_covariance.hpp). Every product is over fixed-size 6x3 / 6x6
// blocks of the observations: no sparse-dense Eigen product, which would open
// an OpenMP team per call in this OpenMP-built library (on a loaded machine
// the team's spinning threads cost more than the products).
#include "hapi_eskf/graph/marginal_covariance.hpp"

#include "../covariance/cpu_linear_algebra.hpp"

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include <utility>

namespace hapi_eskf {
namespace graph {
namespace {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using SparseCols = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Mat63 = Eigen::Matrix<double, 6, 3>;

// J^T J of the problem over `blocks` (points first, then poses), with the
// robust loss's correction as ceres::Covariance evaluates it.
SparseCols information(ceres::Problem* problem, const std::vector<double*>& blocks) {
  ceres::Problem::EvaluateOptions eopt;
  eopt.parameter_blocks = blocks;
  eopt.apply_loss_function = true;
  eopt.num_threads = 1;
  ceres::CRSMatrix crs;
  problem->Evaluate(eopt, nullptr, nullptr, nullptr, &crs);
  const Eigen::Map<const SparseRows> J(crs.num_rows, crs.num_cols, static_cast<int>(crs.values.size()),
                                       crs.rows.data(), crs.cols.data(), crs.values.data());
  return SparseCols(J.transpose() * J);
}

// One point's rows of H: its 3x3 block D and its blocks with the poses that
// observe it (B_a, pose a).
struct PointInformation {
  Mat3 D = Mat3::Zero();
  std::vector<std::pair<int, Mat63>> B;
  Mat63& poseBlock(int a) {
    for (auto& b : B)
      if (b.first == a) return b.second;
    B.emplace_back(a, Mat63::Zero());
    return B.back().second;
  }
};

// H = [D B^T; B A] split into the points' rows and the poses' dense A.
// False when a residual couples two points.
bool splitInformation(const SparseCols& H, int np, std::vector<PointInformation>* points, Eigen::MatrixXd* A) {
  for (int c = 0; c < H.outerSize(); ++c)
    for (SparseCols::InnerIterator it(H, c); it; ++it) {
      const int r = static_cast<int>(it.row());
      if (c < np && r < np) {
        if (r / 3 != c / 3) return false;
        (*points)[c / 3].D(r % 3, c % 3) = it.value();
      } else if (c < np) {
        (*points)[c / 3].poseBlock((r - np) / 6)((r - np) % 6, c % 3) = it.value();
      } else if (r >= np) {
        (*A)(r - np, c - np) = it.value();
      }
    }
  return true;
}

// Inverse of a symmetric positive definite 3x3 block; false when it is not.
bool spdInverse(const Mat3& H, Mat3* inverse) {
  const Eigen::LLT<Mat3> llt(H);
  if (llt.info() != Eigen::Success) return false;
  *inverse = llt.solve(Mat3::Identity());
  return inverse->allFinite();
}

}  // namespace

bool marginalCovariances(ceres::Problem* problem, const std::vector<double*>& points,
                         const std::vector<double*>& poses, std::vector<Mat3>* point_cov,
                         std::vector<Mat6>* pose_cov_tangent) {
  std::vector<double*> blocks(points);
  blocks.insert(blocks.end(), poses.begin(), poses.end());
  const SparseCols H = information(problem, blocks);
  const int np = 3 * static_cast<int>(points.size()), nq = 6 * static_cast<int>(poses.size());
  if (H.rows() != np + nq || H.cols() != np + nq) return false;
  std::vector<PointInformation> info(points.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(nq, nq);  // A, then A - B D^-1 B^T
  if (!splitInformation(H, np, &info, &S)) return false;

  // D_i^-1 and B_i D_i^-1 per point (kept in info[i].D and info[i].B).
  for (PointInformation& p : info) {
    Mat3 D_inv;
    if (!spdInverse(p.D, &D_inv)) return false;
    p.D = D_inv;
    std::vector<Mat63> B(p.B.size());
    for (std::size_t a = 0; a < p.B.size(); ++a) B[a] = p.B[a].second;
    for (std::size_t a = 0; a < p.B.size(); ++a) {
      p.B[a].second = B[a] * D_inv;
      for (std::size_t b = 0; b < p.B.size(); ++b)
        S.block<6, 6>(6 * p.B[a].first, 6 * p.B[b].first).noalias() -= p.B[a].second * B[b].transpose();
    }
  }
  // S^-1 in OpenBLAS's LAPACK where built with it (DPOTRF + DPOTRI, n^3
  // flops for the window's n = 6 x (free keyframes + priors), up to a few
  // hundred), else Eigen.
  Eigen::MatrixXd S_inv = 0.5 * (S + S.transpose());
  if (!cpu_la::inverseSymmetric(CpuLinearAlgebra::kBlas, &S_inv)) return false;

  pose_cov_tangent->resize(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Mat6 C = S_inv.block<6, 6>(6 * k, 6 * k);
    (*pose_cov_tangent)[k] = 0.5 * (C + C.transpose());
  }
  point_cov->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointInformation& p = info[i];
    Mat3 C = p.D;
    for (const auto& a : p.B)
      for (const auto& b : p.B)
        C.noalias() += a.second.transpose() * S_inv.block<6, 6>(6 * a.first, 6 * b.first) * b.second;
    (*point_cov)[i] = 0.5 * (C + C.transpose());
  }
  return true;
}

}  // namespace graph
}  // namespace hapi_eskf
