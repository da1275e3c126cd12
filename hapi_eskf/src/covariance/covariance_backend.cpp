// The input checks of CovarianceBackend, written once for every backend: each
// public method validates here, in the order documented in
// covariance_backend.hpp, before the implementation's do*() runs, so a
// rejected call leaves C and the descriptors unchanged on the CPU and on the
// GPU alike (test/gpu compares the two case by case).
#include "hapi_eskf/covariance/covariance_backend.hpp"

#include "hapi_eskf/covariance_checks.hpp"

#include <vector>

namespace hapi_eskf {
namespace {

// Slots in [0, K).
Status checkSlotRange(const std::vector<int>& slots, int K) {
  for (int s : slots)
    if (s < 0 || s >= K) return Status::kInvalidArgument;
  return Status::kOk;
}

// Slots in [0, K) and pairwise distinct.
Status checkDistinctSlots(const std::vector<int>& slots, int K) {
  std::vector<char> seen(static_cast<std::size_t>(K > 0 ? K : 0), 0);
  for (int s : slots) {
    if (s < 0 || s >= K) return Status::kInvalidArgument;
    if (seen[static_cast<std::size_t>(s)]) return Status::kDuplicateId;
    seen[static_cast<std::size_t>(s)] = 1;
  }
  return Status::kOk;
}

}  // namespace

Status CovarianceBackend::reset(const PoseMat& C_pose) {
  if (C_pose.rows() != pose_dim_ || C_pose.cols() != pose_dim_) return Status::kInvalidArgument;
  if (!C_pose.allFinite()) return Status::kNonFinite;
  if (!isNearlySymmetric(C_pose)) return Status::kInvalidArgument;
  if (!isSymmetricPositiveDefinite(C_pose)) return Status::kNotPositiveDefinite;
  return doReset(C_pose);
}

Status CovarianceBackend::predict(const PoseMat& F, const PoseMat& Q) {
  if (F.rows() != pose_dim_ || F.cols() != pose_dim_ || Q.rows() != pose_dim_ || Q.cols() != pose_dim_)
    return Status::kInvalidArgument;
  if (!F.allFinite() || !Q.allFinite()) return Status::kNonFinite;
  return doPredict(F, Q);
}

Status CovarianceBackend::marginals(const std::vector<int>& slots, std::vector<Mat9>* out) const {
  if (out == nullptr) return Status::kInvalidArgument;
  const Status s = checkSlotRange(slots, numLandmarks());
  if (s != Status::kOk) return s;
  out->resize(slots.size());
  if (slots.empty()) return Status::kOk;
  return doMarginals(slots, out);
}

Status CovarianceBackend::update(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis) {
  if (blocks.empty()) return Status::kEmptyInput;
  if (dx == nullptr) return Status::kInvalidArgument;
  const int K = numLandmarks();
  if (static_cast<int>(blocks.size()) > K) return Status::kCapacityExceeded;
  std::vector<char> used(static_cast<std::size_t>(K), 0);
  for (const MeasurementBlock& b : blocks) {
    if (b.slot < 0 || b.slot >= K) return Status::kInvalidArgument;
    if (used[static_cast<std::size_t>(b.slot)]) return Status::kDuplicateId;
    used[static_cast<std::size_t>(b.slot)] = 1;
    if (!b.H_pose.allFinite() || !b.H_landmark.allFinite() || !b.R.allFinite() || !b.innovation.allFinite())
      return Status::kNonFinite;
  }
  return doUpdate(blocks, dx, nis);
}

Status CovarianceBackend::addLandmarks(const std::vector<NewLandmarkBlock>& blocks) {
  if (blocks.empty()) return Status::kOk;
  if (numLandmarks() + static_cast<long long>(blocks.size()) > capacity()) return Status::kCapacityExceeded;
  for (const NewLandmarkBlock& b : blocks) {
    if (!b.G_pose.allFinite() || !b.G_z.allFinite() || !b.Cz.allFinite()) return Status::kNonFinite;
    if (!isSymmetricPositiveDefinite(b.Cz)) return Status::kNotPositiveDefinite;
    if (descriptorLength() > 0 && b.descriptor == nullptr) return Status::kInvalidArgument;
  }
  return doAddLandmarks(blocks);
}

Status CovarianceBackend::removeLandmarks(const std::vector<int>& slots) {
  if (slots.empty()) return Status::kOk;
  const Status s = checkDistinctSlots(slots, numLandmarks());
  if (s != Status::kOk) return s;
  return doRemoveLandmarks(slots);
}

Status CovarianceBackend::matchDescriptors(const uint8_t* queries, int n_query,
                                           std::vector<DescriptorMatch>* out) const {
  if (out == nullptr || n_query < 0 || (n_query > 0 && queries == nullptr)) return Status::kInvalidArgument;
  out->assign(static_cast<std::size_t>(n_query), DescriptorMatch{});
  if (n_query == 0 || numLandmarks() == 0 || descriptorLength() == 0) return Status::kOk;
  return doMatchDescriptors(queries, n_query, out);
}

}  // namespace hapi_eskf
