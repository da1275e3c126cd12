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
  kNonFinite,          // NaN/Inf position, covariance or response
  kBadCovariance,      // not a covariance (hapi_eskf/covariance_checks.hpp): asymmetric or not PD
  kDescriptorSize,     // descriptors.size() != N * descriptor_length
  kDescriptorLength,   // descriptor_length 0, > kMaxDescriptorLength or != the pool's length
  kDescriptorType,     // descriptor_type differs from the pool's type
  kTooMany,            // N > max_measurements_per_msg
  kFrameId,            // empty frame_id or not the expected camera frame
  kDuplicateId,        // two landmarks with the same id
  kStampBackwards,     // header.stamp not after the last accepted one (StampGuard)
  kCount
};

// Longest binary descriptor we accept (AKAZE full M-LDB is 61 bytes, ORB 32):
// guards the pool against a corrupt first message fixing an absurd length.
constexpr std::uint32_t kMaxDescriptorLength = 512;

constexpr int kRejectCount = static_cast<int>(Reject::kCount);
const char* rejectName(Reject r);

struct ValidationConfig {
  std::uint32_t max_measurements = 2000;
  std::string expected_frame;        // empty: accept any non-empty frame
  int descriptor_type = -1;          // -1: not fixed yet (first message fixes it)
  std::uint32_t descriptor_length = 0;  // 0: not fixed yet
};

struct ValidationResult {
  Reject reason = Reject::kOk;
  std::string detail;
  bool ok() const { return reason == Reject::kOk; }
};

/// Checks everything except stamp ordering, which needs state: the nodelet's
/// hapi_nodelet_kit::StampGuard (a rejection there is Reject::kStampBackwards).
/// Cost O(N): it runs in the ROS callback thread, the filter never sees a
/// message that failed it.
ValidationResult validateLandmarks(const hapi_msgs::StereoLandmarks& msg, const ValidationConfig& cfg);

}  // namespace ros_glue
}  // namespace hapi_eskf
