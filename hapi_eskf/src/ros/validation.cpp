// Checks of hapi_msgs/StereoLandmarks before the filter sees a message; the
// covariance test is the filter's own (hapi_eskf/covariance_checks.hpp).
#include "hapi_eskf/ros/validation.hpp"

#include "hapi_eskf/covariance_checks.hpp"

#include <cmath>
#include <unordered_set>

namespace hapi_eskf {
namespace ros_glue {

const char* rejectName(Reject r) {
  switch (r) {
    case Reject::kOk: return "ok";
    case Reject::kNonFinite: return "non_finite";
    case Reject::kBadCovariance: return "bad_covariance";
    case Reject::kDescriptorSize: return "descriptor_size";
    case Reject::kDescriptorLength: return "descriptor_length";
    case Reject::kDescriptorType: return "descriptor_type";
    case Reject::kTooMany: return "too_many_measurements";
    case Reject::kFrameId: return "frame_id";
    case Reject::kDuplicateId: return "duplicate_id";
    case Reject::kStampBackwards: return "stamp_backwards";
    default: return "unknown";
  }
}

ValidationResult validateLandmarks(const hapi_msgs::StereoLandmarks& msg, const ValidationConfig& cfg) {
  ValidationResult res;
  auto fail = [&](Reject r, const std::string& d) {
    res.reason = r;
    res.detail = d;
    return res;
  };
  const std::size_t n = msg.landmarks.size();
  if (msg.header.frame_id.empty()) return fail(Reject::kFrameId, "empty header.frame_id");
  if (!cfg.expected_frame.empty() && msg.header.frame_id != cfg.expected_frame)
    return fail(Reject::kFrameId, "frame_id '" + msg.header.frame_id + "' != expected '" + cfg.expected_frame + "'");
  if (n > cfg.max_measurements)
    return fail(Reject::kTooMany, std::to_string(n) + " landmarks > max_measurements_per_msg " +
                                      std::to_string(cfg.max_measurements));
  if (msg.descriptor_length == 0) return fail(Reject::kDescriptorLength, "descriptor_length is 0");
  if (msg.descriptor_length > kMaxDescriptorLength)
    return fail(Reject::kDescriptorLength, "descriptor_length " + std::to_string(msg.descriptor_length) + " > " +
                                               std::to_string(kMaxDescriptorLength));
  if (cfg.descriptor_length != 0 && msg.descriptor_length != cfg.descriptor_length)
    return fail(Reject::kDescriptorLength, "descriptor_length " + std::to_string(msg.descriptor_length) +
                                               " != pool's " + std::to_string(cfg.descriptor_length));
  if (cfg.descriptor_type >= 0 && static_cast<int>(msg.descriptor_type) != cfg.descriptor_type)
    return fail(Reject::kDescriptorType, "descriptor_type " + std::to_string(msg.descriptor_type) +
                                             " != pool's " + std::to_string(cfg.descriptor_type));
  if (msg.descriptors.size() != n * static_cast<std::size_t>(msg.descriptor_length))
    return fail(Reject::kDescriptorSize, "descriptors.size() " + std::to_string(msg.descriptors.size()) +
                                             " != N*descriptor_length " +
                                             std::to_string(n * msg.descriptor_length));
  std::unordered_set<std::uint32_t> ids;
  ids.reserve(n * 2);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& l = msg.landmarks[i];
    if (!std::isfinite(l.position.x) || !std::isfinite(l.position.y) || !std::isfinite(l.position.z))
      return fail(Reject::kNonFinite, "landmark " + std::to_string(i) + ": non-finite position");
    for (double v : l.position_covariance)
      if (!std::isfinite(v)) return fail(Reject::kNonFinite, "landmark " + std::to_string(i) + ": non-finite covariance");
    // The filter ranks measurements by response; a NaN would break the sort's ordering.
    if (!std::isfinite(l.response))
      return fail(Reject::kNonFinite, "landmark " + std::to_string(i) + ": non-finite response");
    if (!isSymmetricPositiveDefinite(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
            l.position_covariance.data())))
      return fail(Reject::kBadCovariance, "landmark " + std::to_string(i) + ": covariance not symmetric positive definite");
    if (!ids.insert(l.id).second)
      return fail(Reject::kDuplicateId, "duplicate landmark id " + std::to_string(l.id));
  }
  return res;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
