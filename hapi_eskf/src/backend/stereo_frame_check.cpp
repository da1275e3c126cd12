// The StereoFrame input check (stereo_frame_check.hpp).
#include "hapi_eskf/backend/stereo_frame_check.hpp"

#include "hapi_eskf/covariance_checks.hpp"

#include <cmath>
#include <unordered_set>

namespace hapi_eskf {

Status checkStereoFrame(const StereoFrame& frame, double time, int descriptor_length, int max_measurements) {
  if (!std::isfinite(frame.stamp)) return Status::kNonFinite;
  if (frame.stamp < time) return Status::kInvalidArgument;
  const int n = static_cast<int>(frame.measurements.size());
  if (n == 0) return Status::kEmptyInput;
  if (n > max_measurements) return Status::kCapacityExceeded;
  if (frame.descriptor_length != descriptor_length) return Status::kInvalidArgument;
  if (frame.descriptors.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(frame.descriptor_length))
    return Status::kInvalidArgument;
  std::unordered_set<uint32_t> seen;
  seen.reserve(2 * n);
  for (const auto& m : frame.measurements) {
    if (!m.z.allFinite() || !m.Cz.allFinite() || !std::isfinite(m.response)) return Status::kNonFinite;
    if (!seen.insert(m.frontend_id).second) return Status::kDuplicateId;
  }
  for (const auto& m : frame.measurements)
    if (!isSymmetricPositiveDefinite(m.Cz)) return Status::kNotPositiveDefinite;
  return Status::kOk;
}

}  // namespace hapi_eskf
