// The ROS-free link of pipeline_latency (tools/latency/stereo_frame_link.hpp)
// gives the back end the StereoFrame the two nodelets exchange through
// hapi_msgs/StereoLandmarks (the front end's fillLandmarksMsg, the back end's
// toStereoFrame), and refuses what the front end would not publish.
#include "landmarks_message.hpp"
#include "stereo_frame_link.hpp"

#include <hapi_eskf/ros/conversions.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace {

hapi_frontend::StereoFrameResult makeResult(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  hapi_frontend::StereoFrameResult r;
  r.descriptors = cv::Mat(n, 32, CV_8UC1);
  if (n > 0) cv::randu(r.descriptors, 0, 256);
  for (int i = 0; i < n; ++i) {
    hapi_frontend::StereoLandmarkOut l;
    l.uv_left = Eigen::Vector2d(300 + 10 * u(rng), 200 + 10 * u(rng));
    l.uv_right = l.uv_left - Eigen::Vector2d(20, 0);
    l.position = Eigen::Vector3d(u(rng), u(rng), 0.5 + 0.1 * u(rng));
    const Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    l.covariance = 1e-6 * (A * A.transpose() + Eigen::Matrix3d::Identity());
    l.response = static_cast<float>(100 - i);
    l.rgb = {{static_cast<uint8_t>(i), 20, 30}};
    r.landmarks.push_back(l);
  }
  return r;
}

hapi_eskf::StereoFrame throughTheMessage(const hapi_frontend::StereoFrameResult& r, double stamp) {
  std_msgs::Header h;
  h.stamp.fromSec(stamp);
  hapi_msgs::StereoLandmarks msg;
  EXPECT_EQ(hapi_frontend::fillLandmarksMsg(r, h, &msg), "");
  return hapi_eskf::ros_glue::toStereoFrame(msg);
}

}  // namespace

TEST(LatencyLink, EqualsTheMessagePath) {
  for (int n : {0, 1, 57}) {
    const hapi_frontend::StereoFrameResult r = makeResult(n);
    const double stamp = 1.0e9 + 12.25;
    const hapi_eskf::StereoFrame want = throughTheMessage(r, stamp);
    hapi_eskf::StereoFrame got;
    std::string error;
    ASSERT_TRUE(hapi_latency::toStereoFrame(r, stamp, &got, &error)) << error;
    EXPECT_EQ(got.stamp, want.stamp);
    EXPECT_EQ(got.descriptor_length, want.descriptor_length);
    EXPECT_EQ(got.descriptors, want.descriptors);
    ASSERT_EQ(got.measurements.size(), want.measurements.size());
    for (std::size_t i = 0; i < got.measurements.size(); ++i) {
      const hapi_eskf::StereoMeasurement &a = got.measurements[i], &b = want.measurements[i];
      EXPECT_EQ(a.z, b.z);
      EXPECT_EQ(a.Cz, b.Cz);
      EXPECT_EQ(a.frontend_id, b.frontend_id);
      EXPECT_EQ(a.response, b.response);
      EXPECT_EQ(a.rgb, b.rgb);
    }
  }
}

TEST(LatencyLink, RefusesWhatTheFrontEndWouldNotPublish) {
  hapi_frontend::StereoFrameResult r = makeResult(3);
  r.landmarks[1].covariance(2, 2) = std::numeric_limits<double>::quiet_NaN();
  hapi_eskf::StereoFrame f;
  std::string error;
  EXPECT_FALSE(hapi_latency::toStereoFrame(r, 1.0, &f, &error));
  EXPECT_NE(error.find("landmark 1"), std::string::npos);
  r = makeResult(3);
  r.descriptors = r.descriptors.rowRange(0, 2).clone();
  EXPECT_FALSE(hapi_latency::toStereoFrame(r, 1.0, &f, &error));
  EXPECT_NE(error.find("does not match"), std::string::npos);
}
