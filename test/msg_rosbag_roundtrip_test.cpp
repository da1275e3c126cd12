// hapi_msgs/StereoLandmarks written to a rosbag and read back is unchanged,
// field by field (serialisation of every field, including the nested
// CameraInfo pair and the packed descriptors).
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
    l.u_left = 100.25 + i;
    l.v_left = 200.5 - i;
    l.u_right = 80.125 + i;
    l.v_right = 200.75 - i;
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
  m.left_info.header.frame_id = "stereo_left_optical_frame";
  m.left_info.width = 640;
  m.left_info.height = 480;
  m.left_info.distortion_model = "plumb_bob";
  m.left_info.D = {-0.05, 0.01, 0.001, -0.0005, 0.0};
  m.left_info.K = {500, 0, 320, 0, 500, 240, 0, 0, 1};
  m.right_info = m.left_info;
  m.right_info.header.frame_id = "stereo_right_optical_frame";
  m.right_info.P = {500, 0, 320, -30, 0, 500, 240, 0, 0, 0, 1, 0};
  m.R_left_right = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.t_left_right = {0.06, 0, 0};
  m.pixel_sigma = 0.5;
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
  EXPECT_EQ(got->right_info.P[3], -30.0);
  bag.close();
  std::remove(path.c_str());
}
