// Cheap input validation of hapi_msgs/StereoLandmarks (run in the callback thread).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include <hapi_msgs/StereoLandmarks.h>

namespace hapi_eskf {
namespace ros_glue {

enum class Reject : int {
  kOk = 0,
  kNonFinite,          // NaN/Inf position or covariance
  kBadCovariance,      // non-symmetric or not positive definite
  kDescriptorSize,     // descriptors.size() != N * descriptor_length
  kDescriptorLength,   // descriptor_length 0 or != the pool's length
  kDescriptorType,     // descriptor_type differs from the pool's type
  kTooMany,            // N > max_measurements_per_msg
  kFrameId,            // empty frame_id or not the expected camera frame
  kDuplicateId,        // two landmarks with the same id
  kStampBackwards,     // header.stamp earlier than the last accepted one
  kCount
};

constexpr int kRejectCount = static_cast<int>(Reject::kCount);
const char* rejectName(Reject r);

struct ValidationConfig {
  std::uint32_t max_measurements = 2000;
  std::string expected_frame;        // empty: accept any non-empty frame
  int descriptor_type = -1;          // -1: not fixed yet (first message fixes it)
  std::uint32_t descriptor_length = 0;  // 0: not fixed yet
  double symmetry_tol = 1e-9;        // relative
};

struct ValidationResult {
  Reject reason = Reject::kOk;
  std::string detail;
  bool ok() const { return reason == Reject::kOk; }
};

/// Checks everything except stamp ordering (which needs state; see the nodelet).
ValidationResult validateLandmarks(const hapi_msgs::StereoLandmarks& msg, const ValidationConfig& cfg);

/// True when the 3x3 row-major matrix is finite, symmetric and positive definite.
bool isSymmetricPositiveDefinite3(const double* c, double rel_tol = 1e-9);

}  // namespace ros_glue
}  // namespace hapi_eskf
