// The input check of the associated-frame back ends (associated_frame.hpp).
#include "hapi_eskf/backend/associated_frame.hpp"

#include "hapi_eskf/covariance_checks.hpp"

#include <cmath>
#include <unordered_set>

namespace hapi_eskf {

Status checkAssociatedFrame(const AssociatedFrame& frame, double last_stamp,
                            const std::function<bool(uint64_t)>& known) {
  if (!std::isfinite(frame.stamp)) return Status::kNonFinite;
  if (frame.stamp < last_stamp) return Status::kInvalidArgument;
  std::unordered_set<uint64_t> seen;
  seen.reserve(2 * frame.measurements.size());
  for (const AssociatedMeasurement& m : frame.measurements) {
    if (!m.z.allFinite() || !m.Cz.allFinite()) return Status::kNonFinite;
    if (!isSymmetricPositiveDefinite(m.Cz)) return Status::kNotPositiveDefinite;
    if (m.landmark_id == 0) return Status::kInvalidArgument;
    if (!seen.insert(m.landmark_id).second) return Status::kDuplicateId;
    if (known(m.landmark_id) == m.is_new) return Status::kInvalidArgument;
  }
  return Status::kOk;
}

}  // namespace hapi_eskf
