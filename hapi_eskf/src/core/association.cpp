#include "hapi_eskf/association.hpp"

#include "hapi_eskf/jacobians.hpp"

#include <Eigen/Cholesky>

namespace hapi_eskf {

Status associate(const StereoFrame& frame, const PoseState& pose, const std::vector<Vec3>& positions,
                 const CovarianceBackend& backend, const EskfSettings& settings, Association* out) {
  const int n = static_cast<int>(frame.measurements.size());
  const int K = backend.numLandmarks();
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
  Status st = backend.matchDescriptors(frame.descriptors.data(), n, &matches);
  if (st != Status::kOk) return st;
  std::vector<int> cand_meas, cand_slot;
  for (int i = 0; i < n; ++i) {
    const DescriptorMatch& m = matches[i];
    if (m.best_slot < 0 || m.best_distance > settings.max_hamming) continue;
    // From here on the measurement resembles a pool landmark: even if it is
    // not used (ambiguous, gated out, lost a conflict), adding it would put a
    // second copy of that landmark into the pool, and copies make the ratio
    // test fail for good, so every later observation would add yet another.
    a.may_add[i] = 0;
    // Ratio test on distances: the best must be clearly better than the runner-up.
    if (m.second_slot >= 0 && !(m.best_distance < settings.match_ratio * m.second_distance)) continue;
    cand_meas.push_back(i);
    cand_slot.push_back(m.best_slot);
  }
  a.n_candidates = static_cast<int>(cand_meas.size());
  if (cand_meas.empty()) {
    *out = std::move(a);
    return Status::kOk;
  }

  // 2. Mahalanobis gate with the marginal S_j of each candidate alone.
  std::vector<Mat9> M;
  st = backend.marginals(cand_slot, &M);
  if (st != Status::kOk) return st;
  std::vector<int> owner(K, -1);  // best measurement per landmark
  std::vector<double> owner_d2(K, 0.0);
  for (std::size_t c = 0; c < cand_meas.size(); ++c) {
    const int i = cand_meas[c], k = cand_slot[c];
    const StereoMeasurement& z = frame.measurements[i];
    Mat36 Hp;
    Mat3 Hm;
    measurementJacobian(pose, positions[k], &Hp, &Hm);
    Eigen::Matrix<double, 3, 9> H;
    H << Hp, Hm;
    Mat3 S = H * M[c] * H.transpose() + z.Cz;
    S = 0.5 * (S + S.transpose());
    const Vec3 nu = z.z - measure(pose, positions[k]);
    Eigen::LLT<Mat3> llt(S);
    if (llt.info() != Eigen::Success) {
      ++a.n_gated_out;  // cannot be gated: treated as rejected
      continue;
    }
    const double d2 = llt.matrixL().solve(nu).squaredNorm();
    if (!(d2 <= settings.gate_chi2)) {
      ++a.n_gated_out;
      continue;
    }
    // 3. One measurement per landmark: keep the smallest distance.
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
