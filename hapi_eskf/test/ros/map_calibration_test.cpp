// CameraInfo pair -> the calibration a saved map records (map_calibration.hpp).
#include "hapi_eskf/ros/map_calibration.hpp"

#include <gtest/gtest.h>

#include <limits>

using namespace hapi_eskf;

namespace {

// A rectified pair as stereo_image_proc publishes it: the right's
// P[3] = Tx = -fx' * baseline.
sensor_msgs::CameraInfo info(double tx) {
  sensor_msgs::CameraInfo c;
  c.width = 752;
  c.height = 480;
  c.P = {458.0, 0, 370.0, tx, 0, 457.0, 250.0, 0, 0, 0, 1, 0};
  return c;
}

}  // namespace

TEST(MapCalibration, RectifiedPair) {
  map_file::MapCalibration c;
  std::string why;
  ASSERT_TRUE(ros_glue::toMapCalibration(info(0.0), info(-458.0 * 0.11), &c, &why)) << why;
  EXPECT_EQ(c.width, 752u);
  EXPECT_EQ(c.height, 480u);
  EXPECT_DOUBLE_EQ(c.fx, 458.0);
  EXPECT_DOUBLE_EQ(c.fy, 457.0);
  EXPECT_DOUBLE_EQ(c.cx, 370.0);
  EXPECT_DOUBLE_EQ(c.cy, 250.0);
  EXPECT_DOUBLE_EQ(c.baseline, 0.11);
  EXPECT_FALSE(c.has_imu);  // the mounting is not in camera_info
}

TEST(MapCalibration, RefusalsNameTheirReasonAndLeaveTheOutputAlone) {
  map_file::MapCalibration c;
  c.fx = 1.0;
  std::string why;
  sensor_msgs::CameraInfo smaller = info(-458.0 * 0.11);
  smaller.height = 240;
  EXPECT_FALSE(ros_glue::toMapCalibration(info(0.0), smaller, &c, &why));
  EXPECT_NE(why.find("image size"), std::string::npos) << why;
  why.clear();
  // Tx of the wrong sign (a left-right swap) and an unset right P.
  EXPECT_FALSE(ros_glue::toMapCalibration(info(0.0), info(458.0 * 0.11), &c, &why));
  EXPECT_NE(why.find("rectified stereo pair"), std::string::npos) << why;
  why.clear();
  EXPECT_FALSE(ros_glue::toMapCalibration(info(0.0), sensor_msgs::CameraInfo(), &c, &why));
  EXPECT_FALSE(why.empty());
  sensor_msgs::CameraInfo nan_left = info(0.0);
  nan_left.P[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ros_glue::toMapCalibration(nan_left, info(-458.0 * 0.11), &c, &why));
  EXPECT_DOUBLE_EQ(c.fx, 1.0);
}
