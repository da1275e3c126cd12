// libFuzzer target: hapi_msgs/StereoLandmarks bytes through the back end's
// input path as EskfNodelet runs it: roscpp deserialisation, the nodelet's
// validation (hapi_eskf/ros/validation.hpp) and stamp guard, the message ->
// StereoFrame conversion, then the filter (CPU backend, small pool): the
// first frame with landmarks creates and resets it, later ones run
// Eskf::processFrame (or predictTo when a frame has no landmarks).
// Input: up to 8 records (bounded_message.hpp), one message each.
#include "bounded_message.hpp"
#include "filter_harness.hpp"

#include "hapi_eskf/ros/conversions.hpp"
#include "hapi_eskf/ros/validation.hpp"

#include <hapi_msgs/StereoLandmarks.h>
#include <hapi_nodelet_kit/stamp_guard.hpp>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapi_fuzz::quietRosConsole();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_eskf;
  ros_glue::ValidationConfig validation;
  validation.max_measurements = hapi_fuzz::kMaxMeasurements;
  hapi_nodelet_kit::StampGuard guard(hapi_nodelet_kit::TimeJumpResetParam::kDefault);
  hapi_fuzz::FilterUnderTest filter(MotionModelKind::kConstantVelocity);

  hapi_fuzz::Records records(data, size);
  const std::uint8_t* rec = nullptr;
  std::size_t len = 0;
  for (int i = 0; i < 8 && records.next(&rec, &len); ++i) {
    hapi_msgs::StereoLandmarks msg;
    if (!hapi_fuzz::deserialise<hapi_msgs::StereoLandmarks_>(rec, len, &msg)) continue;
    if (!ros_glue::validateLandmarks(msg, validation).ok()) continue;
    const hapi_nodelet_kit::StampCheck sc = guard.check(static_cast<std::int64_t>(msg.header.stamp.toNSec()));
    if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) continue;
    if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset) filter.requestReset();
    // The first accepted message fixes the frame, a non-empty one the descriptors (as the nodelet).
    if (validation.expected_frame.empty()) validation.expected_frame = msg.header.frame_id;
    if (validation.descriptor_length == 0 && !msg.landmarks.empty()) {
      validation.descriptor_length = msg.descriptor_length;
      validation.descriptor_type = msg.descriptor_type;
    }
    filter.frame(ros_glue::toStereoFrame(msg));
  }
  return 0;
}
