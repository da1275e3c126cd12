// imaging_flow_replay end to end on a synthetic bag (no ROS master): a
// texture moving by a known sub-pixel flow, in several encodings, with a
// frame of an unsupported encoding, a stamp going backwards and a gap. The
// output has one line per usable frame after the first, in the documented
// column layout, and the flows are those rendered. Also the message edge
// (fillFlowMsg) against the same result.
#include "flow_message.hpp"
#include "flow_texture.hpp"

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using hapi_frontend_test::WaveTexture;
constexpr int kW = 200, kH = 160;
const double kCu = 0.5 * (kW - 1), kCv = 0.5 * (kH - 1);

sensor_msgs::Image toMsg(const cv::Mat& m, const std::string& encoding, double t) {
  sensor_msgs::Image msg;
  msg.header.stamp = ros::Time(t);
  msg.header.frame_id = "imaging_optical_frame";
  msg.encoding = encoding;
  msg.width = m.cols;
  msg.height = m.rows;
  msg.step = static_cast<std::uint32_t>(m.step[0]);
  msg.data.assign(m.data, m.data + m.step[0] * m.rows);
  return msg;
}

// The grey image in another encoding with the same grey levels.
sensor_msgs::Image encoded(const cv::Mat& grey, const std::string& encoding, double t) {
  cv::Mat m;
  if (encoding == "bgr8") cv::cvtColor(grey, m, cv::COLOR_GRAY2BGR);
  else if (encoding == "rgb8") cv::cvtColor(grey, m, cv::COLOR_GRAY2RGB);
  else if (encoding == "bgra8") cv::cvtColor(grey, m, cv::COLOR_GRAY2BGRA);
  else if (encoding == "mono16") grey.convertTo(m, CV_16U, 257.0);
  else if (encoding == "32FC1") grey.convertTo(m, CV_32F, 0.01, -0.5);  // a float map of any offset and scale
  else m = grey;
  return toMsg(m, encoding, t);
}

std::vector<std::vector<double>> readRows(const std::string& path) {
  std::vector<std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    std::vector<double> row;
    double v;
    while (is >> v) row.push_back(v);
    rows.push_back(row);
  }
  return rows;
}

TEST(ImagingFlowReplay, WritesTheRenderedFlowOfEveryEncoding) {
  const WaveTexture tex(41);
  const double step_u = 0.37, step_v = -0.21;  // [px/frame]
  const std::vector<std::string> encodings = {"mono8", "bgr8", "rgb8", "bgra8", "mono16", "32FC1", "mono8"};
  const std::string bag_path = ::testing::TempDir() + "imaging_flow_replay_test.bag";
  const std::string out_path = ::testing::TempDir() + "imaging_flow_replay_test.txt";
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    double t = 100.0;
    int k = 0;
    auto frame = [&](int index) {
      const double a[6] = {step_u * index, step_v * index, 0, 0, 0, 0};
      return tex.renderAffine(kW, kH, kCu, kCv, a);
    };
    for (const std::string& e : encodings) {
      bag.write("/imaging/image_raw", ros::Time(t), encoded(frame(k++), e, t));
      t += 0.025;
    }
    // Unsupported encoding: counted, no line, the sequence goes on.
    bag.write("/imaging/image_raw", ros::Time(t), toMsg(frame(k++), "yuv422", t));
    t += 0.025;
    bag.write("/imaging/image_raw", ros::Time(t), encoded(frame(k++), "mono8", t));  // flow over two intervals
    bag.write("/imaging/image_raw", ros::Time(t), encoded(frame(k++), "mono8", t - 1.0));  // backwards: restart
    bag.write("/imaging/image_raw", ros::Time(t), encoded(frame(k++), "mono8", t - 0.975));
    bag.write("/imaging/image_raw", ros::Time(t), encoded(frame(k++), "mono8", t + 5.0));  // gap: restart
    bag.write("/other", ros::Time(t), encoded(frame(0), "mono8", t));
  }
  const std::string cmd = std::string(IMAGING_FLOW_REPLAY) + " " + bag_path + " " + out_path + " --topic /imaging/image_raw";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto rows = readRows(out_path);
  // 12 image messages: the first and the yuv422 one give no line.
  ASSERT_EQ(rows.size(), 10u);
  for (const auto& r : rows) ASSERT_EQ(r.size(), 4u + 6u + 36u + 3u);
  const int expected_status[10] = {0, 0, 0, 0, 0, 0, 0, 2, 0, 2};
  for (int i = 0; i < 10; ++i) {
    const std::vector<double>& r = rows[i];
    EXPECT_EQ(static_cast<int>(r[48]), expected_status[i]) << "line " << i;
    EXPECT_NEAR(r[2], kCu, 1e-3);
    EXPECT_NEAR(r[3], kCv, 1e-3);
    if (expected_status[i] != 0) continue;
    // The line after the unsupported frame spans two frame intervals.
    const double frames = std::round((r[1] - r[0]) / 0.025);
    EXPECT_NEAR(r[4], step_u * frames, 0.02) << "line " << i;
    EXPECT_NEAR(r[5], step_v * frames, 0.02) << "line " << i;
    EXPECT_GT(r[10], 0.0);  // C00
    EXPECT_GE(r[47], r[46] > 0 ? 1.0 : 0.0);
    EXPECT_LE(r[46], r[47]);  // inliers <= tracked
  }
  EXPECT_NEAR(rows[6][1] - rows[6][0], 0.05, 1e-6);
}

TEST(ImagingFlowReplay, MessageCarriesTheResult) {
  hapi_frontend::ImageFlowResult r;
  r.status = hapi_frontend::FlowStatus::kOk;
  r.stamp_ns = 12'500'000'000;
  r.previous_stamp_ns = 12'475'000'000;
  r.u = 320;
  r.v = 240;
  for (int i = 0; i < 6; ++i) r.affine(i) = 0.1 * (i + 1);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) r.covariance(i, j) = i * 6 + j;
  r.inliers = 40;
  r.tracked = 55;
  std_msgs::Header h;
  h.stamp.fromNSec(r.stamp_ns);
  h.frame_id = "imaging_optical_frame";
  hapi_msgs::ImageFlow msg;
  hapi_frontend::fillFlowMsg(r, h, &msg);
  EXPECT_EQ(msg.header.frame_id, "imaging_optical_frame");
  EXPECT_EQ(msg.previous_stamp.toNSec(), 12'475'000'000u);
  EXPECT_EQ(msg.affine[5], r.affine(5));
  EXPECT_EQ(msg.affine_covariance[6 * 2 + 3], 15.0);  // row-major
  EXPECT_EQ(msg.inliers, 40u);
  EXPECT_EQ(msg.tracked, 55u);
  EXPECT_EQ(msg.status, hapi_msgs::ImageFlow::STATUS_OK);
}

}  // namespace
