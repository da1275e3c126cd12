// Host-side validation of backend inputs, done before anything touches the
// device so a rejected call leaves C and the descriptors unchanged. The checks
// and their order (hence the Status returned for an input with several faults)
// mirror the Eigen reference backend (src/core/cpu_backend.cpp); test/gpu
// checks the parity case by case.
#pragma once

#include "hapi_eskf/covariance_backend.hpp"

#include <Eigen/Cholesky>

#include <vector>

namespace hapi_eskf {
namespace cuda {

// Slots in [0, K) and pairwise distinct (removal).
inline Status checkDistinctSlots(const std::vector<int>& slots, int K) {
  std::vector<char> seen(static_cast<std::size_t>(K > 0 ? K : 0), 0);
  for (int s : slots) {
    if (s < 0 || s >= K) return Status::kInvalidArgument;
    if (seen[static_cast<std::size_t>(s)]) return Status::kDuplicateId;
    seen[static_cast<std::size_t>(s)] = 1;
  }
  return Status::kOk;
}

// Slots in [0, K) (marginals may repeat a slot).
inline Status checkSlotRange(const std::vector<int>& slots, int K) {
  for (int s : slots)
    if (s < 0 || s >= K) return Status::kInvalidArgument;
  return Status::kOk;
}

template <int N>
bool nearlySymmetric(const Eigen::Matrix<double, N, N>& M) {
  return (M - M.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + M.cwiseAbs().maxCoeff());
}

inline bool symmetricPd(const Mat3& M) {
  if (!M.allFinite() || !nearlySymmetric<3>(M)) return false;
  Eigen::LLT<Mat3> llt(M);
  return llt.info() == Eigen::Success;
}

inline Status checkPoseCovariance(const Mat12& C) {
  if (!C.allFinite()) return Status::kNonFinite;
  if (!nearlySymmetric<12>(C)) return Status::kInvalidArgument;
  Eigen::LLT<Mat12> llt(C);
  return llt.info() == Eigen::Success ? Status::kOk : Status::kNotPositiveDefinite;
}

inline Status checkUpdate(const std::vector<MeasurementBlock>& blocks, const Eigen::VectorXd* dx, int K) {
  if (blocks.empty()) return Status::kEmptyInput;
  if (dx == nullptr) return Status::kInvalidArgument;
  if (static_cast<int>(blocks.size()) > K) return Status::kCapacityExceeded;
  std::vector<char> used(static_cast<std::size_t>(K), 0);
  for (const auto& b : blocks) {
    if (b.slot < 0 || b.slot >= K) return Status::kInvalidArgument;
    if (used[b.slot]) return Status::kDuplicateId;
    used[b.slot] = 1;
    if (!b.H_pose.allFinite() || !b.H_landmark.allFinite() || !b.R.allFinite() || !b.innovation.allFinite())
      return Status::kNonFinite;
  }
  return Status::kOk;
}

// Call only with a non-empty list (an empty addition is a no-op, kOk).
inline Status checkAdd(const std::vector<NewLandmarkBlock>& blocks, int K, int capacity, int descriptor_length) {
  if (K + static_cast<long long>(blocks.size()) > capacity) return Status::kCapacityExceeded;
  for (const auto& b : blocks) {
    if (!b.G_pose.allFinite() || !b.G_z.allFinite() || !b.Cz.allFinite()) return Status::kNonFinite;
    if (!symmetricPd(b.Cz)) return Status::kNotPositiveDefinite;
    if (descriptor_length > 0 && b.descriptor == nullptr) return Status::kInvalidArgument;
  }
  return Status::kOk;
}

}  // namespace cuda
}  // namespace hapi_eskf
