// hapi_msgs/StereoLandmarks written to a rosbag and read back is unchanged,
// field by field (serialisation of every field, including the packed
// descriptors), and its size on the wire (docs/DESIGN.md "Landmarks message").
#include <gtest/gtest.h>

#include <hapi_msgs/StereoLandmarks.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstdio>
#include <string>
#include <unistd.h>

namespace {

hapi_msgs::StereoLandmarks makeMessage() {
  hapi_msgs::StereoLandmarks m;
  m.header.stamp = ros::Time(1000, 500000000);
  m.header.frame_id = "stereo_left_optical_frame";
  m.header.seq = 7;
  m.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB;
  m.descriptor_length = 32;
  const int n = 5;
  for (int i = 0; i < n; ++i) {
    hapi_msgs::StereoLandmark l;
    l.id = i;
    l.position.x = 0.01 * i;
    l.position.y = -0.02 * i;
    l.position.z = 0.5 + 0.1 * i;
    for (int k = 0; k < 9; ++k) l.position_covariance[k] = (k % 4 == 0) ? 1e-6 * (i + 1) : 1e-8 * k;
    l.response = 12.5f * i;
    l.r = static_cast<uint8_t>(10 * i);
    l.g = static_cast<uint8_t>(20 * i);
    l.b = static_cast<uint8_t>(30 * i);
    m.landmarks.push_back(l);
  }
  for (int i = 0; i < n * 32; ++i) m.descriptors.push_back(static_cast<uint8_t>((i * 37) & 0xff));
  return m;
}

// A frame as the front end publishes it with ORB: n landmarks, 32-byte
// descriptors, the left optical frame of the recording tools.
hapi_msgs::StereoLandmarks orbFrame(int n) {
  hapi_msgs::StereoLandmarks m;
  m.header.frame_id = "stereo_left_optical_frame";
  m.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB;
  m.descriptor_length = 32;
  m.landmarks.resize(n);
  m.descriptors.resize(32 * n);
  return m;
}

}  // namespace

TEST(MsgRosbagRoundtrip, StereoLandmarksUnchanged) {
  char tmpl[] = "/tmp/hapi_roundtrip_XXXXXX";
  const int fd = mkstemp(tmpl);
  ASSERT_GE(fd, 0);
  close(fd);
  const std::string path = std::string(tmpl) + ".bag";
  std::remove(tmpl);

  const hapi_msgs::StereoLandmarks sent = makeMessage();
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.write("/stereo_landmarks", sent.header.stamp, sent);
  }

  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  ASSERT_EQ(view.size(), 1u);
  const auto got = view.begin()->instantiate<hapi_msgs::StereoLandmarks>();
  ASSERT_TRUE(got);
  EXPECT_EQ(view.begin()->getDataType(), "hapi_msgs/StereoLandmarks");
  // Generated messages compare every field with operator==.
  EXPECT_TRUE(*got == sent);
  EXPECT_EQ(got->landmarks.size(), 5u);
  EXPECT_EQ(got->descriptors.size(), 5u * 32u);
  EXPECT_DOUBLE_EQ(got->landmarks[3].position_covariance[4], 4e-6);
  EXPECT_FLOAT_EQ(got->landmarks[2].response, 25.f);
  bag.close();
  std::remove(path.c_str());
}

// Bytes per message: the fixed part (header with its 25-character frame id:
// 41, descriptor type and length: 5, the two array lengths: 8) and per
// landmark the fields the back end reads (id 4, position 24, covariance 72,
// response 4, colour 3) plus its descriptor. A field added to the message
// shows here and in the figure of docs/DESIGN.md.
TEST(MsgRosbagRoundtrip, StereoLandmarksBytesPerMessage) {
  const uint32_t fixed = ros::serialization::serializationLength(orbFrame(0));
  const uint32_t per_landmark = ros::serialization::serializationLength(orbFrame(1)) - fixed;
  EXPECT_EQ(fixed, 54u);
  EXPECT_EQ(per_landmark, 107u + 32u);
  for (int n : {200, 300, 900})
    std::printf("[wire] StereoLandmarks, %d ORB landmarks: %u bytes\n", n,
                ros::serialization::serializationLength(orbFrame(n)));
}
