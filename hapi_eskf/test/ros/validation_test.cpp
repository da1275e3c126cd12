// Every Reject reason of validateLandmarks. (The stamp order rule,
// Reject::kStampBackwards, is hapi_nodelet_kit's StampGuard, tested there.)
#include "hapi_eskf/ros/validation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace hapi_eskf::ros_glue;

namespace {

hapi_msgs::StereoLandmarks goodMessage(int n = 3, std::uint32_t dlen = 32) {
  hapi_msgs::StereoLandmarks m;
  m.header.frame_id = "stereo_left_optical_frame";
  m.header.stamp.fromSec(10.0);
  m.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB;
  m.descriptor_length = dlen;
  m.descriptors.assign(n * dlen, 0xA5);
  m.landmarks.resize(n);
  for (int i = 0; i < n; ++i) {
    auto& l = m.landmarks[i];
    l.id = i;
    l.position.x = 0.1 * i;
    l.position.y = -0.2;
    l.position.z = 2.0 + i;
    l.position_covariance = {1e-4, 1e-6, 0, 1e-6, 2e-4, 0, 0, 0, 5e-4};
    l.response = 10.f;
  }
  return m;
}

ValidationConfig cfg() {
  ValidationConfig c;
  c.max_measurements = 100;
  return c;
}

Reject check(const hapi_msgs::StereoLandmarks& m, const ValidationConfig& c = cfg()) {
  return validateLandmarks(m, c).reason;
}

}  // namespace

TEST(Validation, GoodMessagePasses) {
  EXPECT_EQ(check(goodMessage()), Reject::kOk);
  EXPECT_EQ(check(goodMessage(0)), Reject::kOk);  // nothing seen is valid input
}

TEST(Validation, NonFinitePositionCovarianceResponse) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto m = goodMessage();
  m.landmarks[1].position.y = nan;
  EXPECT_EQ(check(m), Reject::kNonFinite);
  m = goodMessage();
  m.landmarks[2].position_covariance[4] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(check(m), Reject::kNonFinite);
  m = goodMessage();
  m.landmarks[0].response = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(check(m), Reject::kNonFinite);
}

TEST(Validation, BadCovariance) {
  auto m = goodMessage();
  m.landmarks[0].position_covariance = {1e-4, 0, 0, 0, -1e-4, 0, 0, 0, 1e-4};  // indefinite
  EXPECT_EQ(check(m), Reject::kBadCovariance);
  m = goodMessage();
  m.landmarks[1].position_covariance[1] = 5e-5;  // asymmetric (c01 != c10)
  EXPECT_EQ(check(m), Reject::kBadCovariance);
  m = goodMessage();
  m.landmarks[2].position_covariance = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // singular
  EXPECT_EQ(check(m), Reject::kBadCovariance);
}

TEST(Validation, DescriptorSizeLengthType) {
  auto m = goodMessage();
  m.descriptors.pop_back();
  EXPECT_EQ(check(m), Reject::kDescriptorSize);
  m = goodMessage();
  m.descriptor_length = 0;
  EXPECT_EQ(check(m), Reject::kDescriptorLength);
  m = goodMessage(1, kMaxDescriptorLength + 1);
  EXPECT_EQ(check(m), Reject::kDescriptorLength);
  ValidationConfig c = cfg();
  c.descriptor_length = 61;
  EXPECT_EQ(check(goodMessage(), c), Reject::kDescriptorLength);
  c = cfg();
  c.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_AKAZE;
  EXPECT_EQ(check(goodMessage(), c), Reject::kDescriptorType);
}

TEST(Validation, TooMany) {
  ValidationConfig c = cfg();
  c.max_measurements = 2;
  EXPECT_EQ(check(goodMessage(3), c), Reject::kTooMany);
  EXPECT_EQ(check(goodMessage(2), c), Reject::kOk);
}

TEST(Validation, FrameId) {
  auto m = goodMessage();
  m.header.frame_id.clear();
  EXPECT_EQ(check(m), Reject::kFrameId);
  ValidationConfig c = cfg();
  c.expected_frame = "other_frame";
  EXPECT_EQ(check(goodMessage(), c), Reject::kFrameId);
}

TEST(Validation, DuplicateId) {
  auto m = goodMessage();
  m.landmarks[2].id = m.landmarks[0].id;
  EXPECT_EQ(check(m), Reject::kDuplicateId);
}

TEST(Validation, EveryReasonHasAName) {
  for (int r = 0; r < kRejectCount; ++r) EXPECT_STRNE(rejectName(static_cast<Reject>(r)), "unknown");
}
