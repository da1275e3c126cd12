#include "hapi_eskf/backend/association.hpp"

#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/so3.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include <algorithm>
#include <cstdint>
#include <random>

namespace hapi_eskf {
namespace {

// Least-squares rigid transform X ~ R Z + t over the given indices (Kabsch),
// used for the 3-point hypotheses.
void fitRigid(const std::vector<Vec3>& X, const std::vector<Vec3>& Z, const std::vector<int>& idx, Mat3* R, Vec3* t) {
  Vec3 mx = Vec3::Zero(), mz = Vec3::Zero();
  for (int i : idx) { mx += X[i]; mz += Z[i]; }
  mx /= static_cast<double>(idx.size());
  mz /= static_cast<double>(idx.size());
  Mat3 cov = Mat3::Zero();
  for (int i : idx) cov += (X[i] - mx) * (Z[i] - mz).transpose();
  Eigen::JacobiSVD<Mat3> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) D(2, 2) = -1.0;
  *R = svd.matrixU() * D * svd.matrixV().transpose();
  *t = mx - *R * mz;
}

using Vec6 = Eigen::Matrix<double, 6, 1>;

// Residual e = X - (R Z + t) and its Jacobian w.r.t. [dtheta, dt] for the
// update R <- Exp(dtheta) R, t <- t + dt: de/ddtheta = [R Z]x, de/ddt = -I.
Eigen::Matrix<double, 3, 6> residualJacobian(const Mat3& R, const Vec3& z) {
  Eigen::Matrix<double, 3, 6> J;
  J << skew(R * z), -Mat3::Identity();
  return J;
}

// Weighted Gauss-Newton refit of (R, t) on the given pairs with their full
// covariances S_i = W_i + R C_z,i R^T (stereo points are very anisotropic, so
// scalar weights would let the noisy depth direction spoil the rotation).
// *P receives the 6x6 covariance of the fit. False when the normal equations
// are singular.
bool refineRigid(const std::vector<Vec3>& X, const std::vector<Vec3>& Z, const std::vector<Mat3>& W,
                 const std::vector<Mat3>& Cz, const std::vector<int>& idx, Mat3* R, Vec3* t, Mat6* P) {
  for (int it = 0; it < 5; ++it) {
    Mat6 A = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    for (int i : idx) {
      const Mat3 S = W[i] + *R * Cz[i] * R->transpose();
      const Mat3 Si = S.llt().solve(Mat3::Identity());
      const Eigen::Matrix<double, 3, 6> J = residualJacobian(*R, Z[i]);
      const Vec3 e = X[i] - (*R * Z[i] + *t);
      A += J.transpose() * Si * J;
      g += J.transpose() * Si * e;
    }
    Eigen::LDLT<Mat6> ldlt(A);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
    const Vec6 d = -ldlt.solve(g);  // minimises |e + J d|^2_Si
    if (!d.allFinite()) return false;
    *R = quatExp(d.head<3>()).toRotationMatrix() * *R;
    *t += d.tail<3>();
    *P = ldlt.solve(Mat6::Identity());
    if (d.norm() < 1e-10) break;
  }
  return true;
}

// Inlier flags of the hypothesis (R, t) and their count; *cost = sum of the
// inliers' squared Mahalanobis distances (tie-break between equal counts).
// P (optional): covariance of (R, t), added to each pair's S.
int scoreRigid(const std::vector<Vec3>& X, const std::vector<Vec3>& Z, const std::vector<Mat3>& W,
               const std::vector<Mat3>& Cz, const Mat3& R, const Vec3& t, const Mat6* P, double chi2,
               std::vector<char>* inl, double* cost) {
  int n = 0;
  *cost = 0.0;
  inl->assign(X.size(), 0);
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Vec3 e = X[i] - (R * Z[i] + t);
    Mat3 S = W[i] + R * Cz[i] * R.transpose();
    if (P) {
      const Eigen::Matrix<double, 3, 6> J = residualJacobian(R, Z[i]);
      S += J * *P * J.transpose();
    }
    Eigen::LLT<Mat3> llt(S);
    if (llt.info() != Eigen::Success) continue;
    const double d2 = llt.matrixL().solve(e).squaredNorm();
    if (d2 <= chi2) {
      (*inl)[i] = 1;
      ++n;
      *cost += d2;
    }
  }
  return n;
}

}  // namespace

// RANSAC over 3-point samples, then the best set is grown by Gauss-Newton
// refits with full covariances (the fit's own uncertainty included in the
// test). Deterministic (fixed seed, own index draw) so that every backend sees
// the same result. Returns the inlier flags, or empty when no hypothesis is
// supported by at least 3 pairs (then nothing is decided here).
std::vector<char> ransacRigidInliers(const std::vector<Vec3>& X, const std::vector<Vec3>& Z,
                                     const std::vector<Mat3>& W, const std::vector<Mat3>& Cz, int iterations,
                                     double chi2, Mat3* R_out, Vec3* t_out) {
  const int n = static_cast<int>(X.size());
  if (n < 3) return {};
  std::mt19937 rng(0x5eed1234u + static_cast<uint32_t>(n));
  std::vector<char> best, cur;
  int best_n = 0;
  double best_cost = 0.0;
  Mat3 best_R = Mat3::Identity();
  Vec3 best_t = Vec3::Zero();
  for (int it = 0; it < iterations; ++it) {
    const int a = static_cast<int>(rng() % static_cast<uint32_t>(n));
    const int b = static_cast<int>(rng() % static_cast<uint32_t>(n));
    const int c = static_cast<int>(rng() % static_cast<uint32_t>(n));
    if (a == b || a == c || b == c) continue;
    // Degenerate (nearly collinear) samples fix no rotation about their line.
    if ((Z[b] - Z[a]).cross(Z[c] - Z[a]).norm() < 1e-6) continue;
    Mat3 R;
    Vec3 t;
    fitRigid(X, Z, {a, b, c}, &R, &t);
    double cost;
    const int k = scoreRigid(X, Z, W, Cz, R, t, nullptr, chi2, &cur, &cost);
    if (k > best_n || (k == best_n && k > 0 && cost < best_cost)) {
      best_n = k;
      best_cost = cost;
      best = cur;
      best_R = R;
      best_t = t;
    }
  }
  if (best_n < 3) return {};
  // A 3-point hypothesis carries the noise of its sample: refit on the
  // inliers and rescore until the set stops changing (a few rounds).
  for (int round = 0; round < 4; ++round) {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i)
      if (best[i]) idx.push_back(i);
    Mat3 R;
    Vec3 t;
    fitRigid(X, Z, idx, &R, &t);
    Mat6 P;
    if (!refineRigid(X, Z, W, Cz, idx, &R, &t, &P)) break;
    double cost;
    const int k = scoreRigid(X, Z, W, Cz, R, t, &P, chi2, &cur, &cost);
    if (k < 3) break;
    best_R = R;  // the refit is better than the hypothesis that found the set
    best_t = t;
    if (cur == best) break;
    best_n = k;
    best = cur;
  }
  if (R_out) *R_out = best_R;
  if (t_out) *t_out = best_t;
  return best;
}

Status associate(const StereoFrame& frame, const PoseState& pose, const Mat6& camera_jacobian,
                 const std::vector<Vec3>& positions, const AssociationSource& source, const AssociationSettings& settings,
                 Association* out) {
  const int n = static_cast<int>(frame.measurements.size());
  const int K = source.numLandmarks();
  if (!out || static_cast<int>(positions.size()) != K) return Status::kInvalidArgument;
  Association a;
  a.slot.assign(n, -1);
  a.d2.assign(n, 0.0);
  a.may_add.assign(n, 1);
  if (n == 0 || K == 0) {
    *out = std::move(a);
    return Status::kOk;
  }

  // 1. Descriptors: best and second best over the whole pool.
  std::vector<DescriptorMatch> matches;
  Status st = source.matchDescriptors(frame.descriptors.data(), n, &matches);
  if (st != Status::kOk) return st;
  std::vector<int> cand_meas, cand_slot;
  for (int i = 0; i < n; ++i) {
    const DescriptorMatch& m = matches[i];
    if (!m.within(settings.max_hamming)) continue;
    // From here on the measurement resembles a pool landmark: unless it turns
    // out to be far from it (step 3, copy_chi2), adding it when it is not
    // used (ambiguous, gated out, lost a conflict) would put a second copy of
    // that landmark into the pool, and copies make the ratio test fail for
    // good, so every later observation would add yet another.
    a.may_add[i] = 0;
    // Ratio test on distances: the best must be clearly better than the runner-up.
    if (!m.distinct(settings.match_ratio)) continue;
    cand_meas.push_back(i);
    cand_slot.push_back(m.best_slot);
  }
  a.n_candidates = static_cast<int>(cand_meas.size());
  if (cand_meas.empty()) {
    *out = std::move(a);
    return Status::kOk;
  }

  std::vector<Mat9> M;
  st = source.marginals(cand_slot, &M);
  if (st != Status::kOk) return st;

  // 2. Geometric consistency (RANSAC rigid fit), see EskfSettings::ransac_iterations.
  std::vector<char> consistent(cand_meas.size(), 1);
  if (settings.ransac_iterations > 0 && cand_meas.size() >= 6) {
    std::vector<Vec3> X(cand_meas.size()), Z(cand_meas.size());
    std::vector<Mat3> W(cand_meas.size()), Cz(cand_meas.size());
    for (std::size_t c = 0; c < cand_meas.size(); ++c) {
      X[c] = positions[cand_slot[c]];
      Z[c] = frame.measurements[cand_meas[c]].z;
      // The map's own noise per point, not the landmark's marginal: the fit's
      // free R, t absorb the error the whole map shares (the pose it was
      // built from), and that shared part dominates the marginal right after
      // a start or an outage (cm while the velocity is unknown), which would
      // let wrong associations through. What a rigid fit cannot absorb is
      // each point's own noise from its initialisation, of the size of its
      // measurement noise now, in the fit's own axes: W_i = R_f C_z R_f^T,
      // i.e. S_i = R_f (2 C_z) R_f^T (docs/DESIGN.md "Gate each association").
      // Not the predicted orientation: after an outage it can be far off, and
      // C_z is long along the ray.
      W[c].setZero();
      Cz[c] = 2.0 * frame.measurements[cand_meas[c]].Cz;
    }
    const std::vector<char> inl =
        ransacRigidInliers(X, Z, W, Cz, settings.ransac_iterations, settings.gate_chi2, &a.fit_R, &a.fit_t);
    if (!inl.empty()) {
      consistent = inl;
      a.fit_inliers = static_cast<int>(std::count(inl.begin(), inl.end(), 1));
    }
  }

  // 3. Mahalanobis gate with the marginal S_j of each candidate alone. A
  // candidate rejected here or by RANSAC that is far from its landmark
  // (beyond copy_chi2 in the same metric) is another point with a similar
  // descriptor: it may start a landmark.
  std::vector<int> owner(K, -1);  // best measurement per landmark
  std::vector<double> owner_d2(K, 0.0);
  const bool tell_copies = settings.copy_chi2 > 0.0;
  auto rejectedByRansac = [&a] {
    ++a.n_gated_out;
    ++a.n_ransac_out;
  };
  for (std::size_t c = 0; c < cand_meas.size(); ++c) {
    const int i = cand_meas[c], k = cand_slot[c];
    // Rejected by RANSAC: its S is needed only to tell a copy from another
    // point.
    if (!consistent[c] && !tell_copies) {
      rejectedByRansac();
      continue;
    }
    const StereoMeasurement& z = frame.measurements[i];
    Mat36 Hp;
    Mat3 Hm;
    measurementJacobian(pose, positions[k], &Hp, &Hm);
    Eigen::Matrix<double, 3, 9> H;
    H << Hp * camera_jacobian, Hm;
    Mat3 S = H * M[c] * H.transpose() + z.Cz;
    S = 0.5 * (S + S.transpose());
    const Vec3 nu = z.z - measure(pose, positions[k]);
    Eigen::LLT<Mat3> llt(S);
    if (llt.info() != Eigen::Success) {
      // Cannot be gated: treated as rejected (and as a copy).
      if (!consistent[c])
        rejectedByRansac();
      else
        ++a.n_gated_out;
      continue;
    }
    const double d2 = llt.matrixL().solve(nu).squaredNorm();
    if (tell_copies && d2 > settings.copy_chi2) a.may_add[i] = 1;
    if (!consistent[c]) {
      rejectedByRansac();
      continue;
    }
    if (!(d2 <= settings.gate_chi2)) {
      ++a.n_gated_out;
      if (a.fit_inliers > 0) ++a.n_fit_inliers_gated_out;
      continue;
    }
    // 4. One measurement per landmark: keep the smallest distance.
    if (owner[k] < 0 || d2 < owner_d2[k]) {
      if (owner[k] >= 0) {
        a.slot[owner[k]] = -1;
        a.d2[owner[k]] = 0.0;
        a.may_add[owner[k]] = 0;
        ++a.n_conflicts;
      }
      owner[k] = i;
      owner_d2[k] = d2;
      a.slot[i] = k;
      a.d2[i] = d2;
      a.may_add[i] = 0;
    } else {
      a.may_add[i] = 0;
      ++a.n_conflicts;
    }
  }
  *out = std::move(a);
  return Status::kOk;
}

}  // namespace hapi_eskf
