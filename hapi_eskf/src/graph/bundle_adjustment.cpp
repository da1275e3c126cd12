// The Ceres problem of Graph SLAM (bundle_adjustment.hpp). Pose parameters
// are [p (3), q (4, Eigen's x y z w)] with Ceres's product manifold
// R^3 x EigenQuaternion, whose rotation perturbation is global
// (q <- Exp(d) q); covariances are mapped to the filter's local dtheta
// (R = R_hat Exp(dtheta)) as dtheta = R^T d (docs/DESIGN.md "Graph SLAM").
#include "hapi_eskf/graph/bundle_adjustment.hpp"

#include "hapi_eskf/graph/marginal_covariance.hpp"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <Eigen/Cholesky>

#include <memory>
#include <unordered_map>

namespace hapi_eskf {
namespace graph {
namespace {

// r = W (z - R^T (m - p)), W = L^-1 (L L^T = Cz), autodiff'ed.
struct StereoPointResidual {
  StereoPointResidual(const Vec3& z, const Mat3& Cz) : z_(z) {
    const Mat3 L = Cz.llt().matrixL();
    W_ = L.triangularView<Eigen::Lower>().solve(Mat3::Identity());
  }
  template <typename T>
  bool operator()(const T* pose, const T* landmark, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(pose);
    Eigen::Map<const Eigen::Quaternion<T>> q(pose + 3);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> m(landmark);
    const Eigen::Matrix<T, 3, 1> h = q.conjugate() * (m - p);
    const Eigen::Matrix<T, 3, 1> e = z_.cast<T>() - h;
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = W_.cast<T>() * e;
    return true;
  }
  Vec3 z_;
  Mat3 W_;
};

// A pose prior, r = W [p - p0; Log(q q0^-1)] with W^T W = G^-1, G the
// pose's covariance in Ceres's tangent space (global rotation increment).
// Used only for the covariances of a window: an old keyframe held fixed in
// the solve stands for its own uncertainty there (docs/DESIGN.md "Graph
// SLAM", covariances). Its residual is zero at the solution.
struct PosePriorResidual {
  PosePriorResidual(const Vec3& p0, const Eigen::Quaterniond& q0, const Mat6& G) : p0_(p0), q0_(q0) {
    const Mat6 L = G.llt().matrixL();
    W_ = L.triangularView<Eigen::Lower>().solve(Mat6::Identity());
  }
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(pose);
    Eigen::Map<const Eigen::Quaternion<T>> q(pose + 3);
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = p - p0_.cast<T>();
    Eigen::Quaternion<T> d = q * q0_.conjugate().cast<T>();
    if (d.w() < T(0)) d.coeffs() = -d.coeffs();
    e.template tail<3>() = T(2) * d.vec();  // Log for the small angles of a prior at its mean
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = W_.cast<T>() * e;
    return true;
  }
  Vec3 p0_;
  Eigen::Quaterniond q0_;
  Mat6 W_;
};

// [dp world, dtheta local] <-> Ceres's [dp, d global]: d = R dtheta.
Mat6 localToGlobal(const Eigen::Quaterniond& q) {
  Mat6 J = Mat6::Identity();
  J.block<3, 3>(3, 3) = q.normalized().toRotationMatrix();
  return J;
}

bool hasCovariance(const Mat6& C) { return C.allFinite() && C.diagonal().minCoeff() > 0.0; }

ceres::LossFunction* makeLoss(const GraphSettings& s) {
  // Ceres's losses act on s = |r|^2 with scale a: Huber(a) is quadratic up
  // to |r| = a.
  switch (s.robust_loss) {
    case RobustLoss::kHuber: return new ceres::HuberLoss(s.robust_scale);
    case RobustLoss::kCauchy: return new ceres::CauchyLoss(s.robust_scale);
    case RobustLoss::kNone: break;
  }
  return nullptr;
}

using PoseBlock = Eigen::Matrix<double, 7, 1>;

}  // namespace

Status adjustBundle(const GraphSettings& settings, const BundleOptions& options, const std::vector<char>& constant,
                    GraphMap* map, BundleReport* report) {
  BundleReport rep;
  if (!map || constant.size() != map->keyframes.size()) return Status::kInvalidArgument;
  if (map->observations.empty()) return Status::kEmptyInput;
  // Parameter copies: Ceres writes into them; the map changes only on success.
  std::vector<PoseBlock> poses(map->keyframes.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    poses[k].head<3>() = map->keyframes[k].p;
    poses[k].tail<4>() = map->keyframes[k].q.normalized().coeffs();
  }
  std::unordered_map<uint64_t, Vec3> points;
  for (const Observation& o : map->observations) {
    if (o.keyframe < 0 || o.keyframe >= static_cast<int>(poses.size()) || !map->landmarks.count(o.landmark))
      return Status::kInvalidArgument;
    points.emplace(o.landmark, map->landmarks.at(o.landmark).position);
  }

  ceres::Problem::Options popt;
  popt.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(popt);
  // One loss object per residual: ownership is simplest, the objects are tiny.
  std::vector<char> used(poses.size(), 0);
  for (const Observation& o : map->observations) {
    auto* cost = new ceres::AutoDiffCostFunction<StereoPointResidual, 3, 7, 3>(new StereoPointResidual(o.z, o.Cz));
    problem.AddResidualBlock(cost, makeLoss(settings), poses[o.keyframe].data(), points.at(o.landmark).data());
    used[o.keyframe] = 1;
  }
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!used[k]) continue;
    problem.SetManifold(poses[k].data(),
                        new ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::EigenQuaternionManifold>(
                            ceres::EuclideanManifold<3>(), ceres::EigenQuaternionManifold()));
    if (constant[k]) problem.SetParameterBlockConstant(poses[k].data());
  }
  rep.residuals = problem.NumResidualBlocks();

  ceres::Solver::Options sopt;
  sopt.max_num_iterations = options.max_iterations;
  sopt.linear_solver_type = options.sparse ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
  sopt.num_threads = 1;  // the frame thread keeps the other core
  sopt.logging_type = ceres::SILENT;
  std::string why;
  if (!sopt.IsValid(&why)) sopt.linear_solver_type = ceres::DENSE_SCHUR;
  ceres::Solver::Summary summary;
  ceres::Solve(sopt, &problem, &summary);
  rep.iterations = static_cast<int>(summary.iterations.size());
  rep.initial_cost = summary.initial_cost;
  rep.final_cost = summary.final_cost;
  rep.usable = summary.IsSolutionUsable();
  if (!rep.usable) {
    if (report) *report = rep;
    return Status::kOk;
  }

  // Covariances at the solution (docs/DESIGN.md "Graph SLAM", covariances).
  int newest_free = -1;
  for (std::size_t k = 0; k < poses.size(); ++k)
    if (used[k] && !constant[k]) newest_free = static_cast<int>(k);
  std::unordered_map<uint64_t, Mat3> point_cov;
  std::unordered_map<int, Mat6> keyframe_cov;
  if (options.covariances) {
    // Constant keyframes with a covariance become priors of themselves. Their
    // errors are correlated (they share the older map's drift) but the
    // cross-covariances are not kept: covariance intersection with equal
    // weights, i.e. each prior's covariance times their number, is the fusion
    // that stays consistent whatever the correlations (Julier and Uhlmann
    // 1997; docs/DESIGN.md "Graph SLAM", covariances).
    int n_priors = 0;
    for (std::size_t k = 0; k < poses.size(); ++k)
      n_priors += used[k] && constant[k] && hasCovariance(map->keyframes[k].covariance);
    std::vector<double*> point_blocks, pose_blocks;
    std::vector<int> pose_index;  // keyframe of each pose block
    for (std::size_t k = 0; k < poses.size(); ++k) {
      if (!used[k]) continue;
      if (constant[k]) {
        const Mat6& C = map->keyframes[k].covariance;
        if (!hasCovariance(C)) continue;
        const Mat6 J = localToGlobal(map->keyframes[k].q);
        const Mat6 G = static_cast<double>(n_priors) * J * C * J.transpose();
        if (G.llt().info() != Eigen::Success) continue;
        problem.SetParameterBlockVariable(poses[k].data());
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PosePriorResidual, 6, 7>(new PosePriorResidual(
                                     map->keyframes[k].p, map->keyframes[k].q, 0.5 * (G + G.transpose()))),
                                 nullptr, poses[k].data());
      }
      pose_blocks.push_back(poses[k].data());
      pose_index.push_back(static_cast<int>(k));
    }
    std::vector<uint64_t> point_ids;
    for (auto& kv : points) {
      point_ids.push_back(kv.first);
      point_blocks.push_back(kv.second.data());
    }
    std::vector<Mat3> point_blocks_cov;
    std::vector<Mat6> pose_blocks_cov;
    if (marginalCovariances(&problem, point_blocks, pose_blocks, &point_blocks_cov, &pose_blocks_cov)) {
      rep.covariance_ok = true;
      for (std::size_t i = 0; i < point_ids.size(); ++i) point_cov[point_ids[i]] = point_blocks_cov[i];
      for (std::size_t b = 0; b < pose_blocks.size(); ++b) {
        const int k = pose_index[b];
        if (constant[k]) continue;
        // Tangent [dp, d global] -> [dp world, dtheta local].
        const Mat6 Jt = localToGlobal(Eigen::Quaterniond(poses[k].tail<4>().data())).transpose();
        const Mat6 C = Jt * pose_blocks_cov[b] * Jt.transpose();
        keyframe_cov[k] = 0.5 * (C + C.transpose());
      }
      if (newest_free >= 0) rep.newest_pose_covariance = keyframe_cov.at(newest_free);
    }
  }

  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!used[k] || constant[k]) continue;
    map->keyframes[k].p = poses[k].head<3>();
    map->keyframes[k].q = Eigen::Quaterniond(poses[k].tail<4>().data()).normalized();
    const auto it = keyframe_cov.find(static_cast<int>(k));
    if (it != keyframe_cov.end()) map->keyframes[k].covariance = it->second;
  }
  for (const auto& kv : points) map->landmarks.at(kv.first).position = kv.second;
  for (const auto& kv : points) {
    GraphLandmark& l = map->landmarks.at(kv.first);
    const auto it = point_cov.find(kv.first);
    l.covariance = it != point_cov.end() ? it->second : conditionalLandmarkCovariance(*map, l);
  }
  if (report) *report = rep;
  return Status::kOk;
}

}  // namespace graph
}  // namespace hapi_eskf
