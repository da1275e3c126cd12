// SurfaceMotionNodelet's conversions (src/ros/surface_motion_conversions.hpp):
// the map's PointCloud2 (dense float/double x y z, bad layouts refused),
// CameraInfo (plumb_bob or none), ImageFlow and Odometry, and a message that
// carries no value when its status is not OK.
#include "surface_motion_conversions.hpp"

#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <cmath>

namespace hapi_eskf {
namespace ros_glue {
namespace {

sensor_msgs::PointCloud2 cloud(int n) {
  sensor_msgs::PointCloud2 c;
  sensor_msgs::PointCloud2Modifier mod(c);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(n);
  sensor_msgs::PointCloud2Iterator<float> x(c, "x"), y(c, "y"), z(c, "z");
  for (int i = 0; i < n; ++i, ++x, ++y, ++z) {
    *x = 0.1f * i;
    *y = 0.0f;
    *z = i == 1 ? std::nanf("") : 0.3f;
  }
  return c;
}

TEST(SurfaceMotionConversions, PointsSkipNaNAndRefuseBadLayouts) {
  std::vector<Vec3> pts;
  EXPECT_EQ(toPoints(cloud(4), &pts), "");
  ASSERT_EQ(pts.size(), 3u);  // the NaN point skipped
  EXPECT_NEAR(pts[2].x(), 0.3, 1e-6);
  EXPECT_EQ(toPoints(cloud(0), &pts), "");
  EXPECT_TRUE(pts.empty());
  sensor_msgs::PointCloud2 bad = cloud(4);
  bad.data.resize(bad.data.size() - 3);  // not whole points
  EXPECT_NE(toPoints(bad, &pts), "");
  bad = cloud(4);
  bad.row_step += 4;
  EXPECT_NE(toPoints(bad, &pts), "");
  bad = cloud(4);
  bad.fields.pop_back();  // no z
  EXPECT_NE(toPoints(bad, &pts), "");
  bad = cloud(4);
  bad.fields[0].offset = bad.point_step;  // beyond the point
  EXPECT_NE(toPoints(bad, &pts), "");
}

TEST(SurfaceMotionConversions, CameraInfoPlumbBobOrNone) {
  sensor_msgs::CameraInfo c;
  c.width = 640;
  c.height = 480;
  c.K = {500, 0, 320, 0, 510, 240, 0, 0, 1};
  surface_motion::ImagingCamera cam;
  EXPECT_EQ(toImagingCamera(c, 40, &cam), "");
  EXPECT_EQ(cam.fy, 510);
  c.distortion_model = "plumb_bob";
  c.D = {-0.2, 0.05, 0.001, 0.0, 0.0};
  EXPECT_EQ(toImagingCamera(c, 40, &cam), "");
  EXPECT_EQ(cam.distortion[0], -0.2);
  c.distortion_model = "equidistant";
  c.D = {0.1, 0.0, 0.0, 0.0};
  EXPECT_NE(toImagingCamera(c, 40, &cam), "");
  c.D.clear();
  c.K[0] = 0;  // no focal length
  EXPECT_NE(toImagingCamera(c, 40, &cam), "");
  EXPECT_EQ(cam.distortion[0], -0.2);  // unchanged on failure
}

TEST(SurfaceMotionConversions, FlowOdometryAndMessage) {
  hapi_msgs::ImageFlow f;
  f.header.stamp = ros::Time(10.05);
  f.previous_stamp = ros::Time(10.025);
  f.affine = {1, 2, 3, 4, 5, 6};
  f.affine_covariance[0] = 0.25;
  f.status = hapi_msgs::ImageFlow::STATUS_OK;
  const surface_motion::FlowMeasurement m = toFlowMeasurement(f);
  EXPECT_NEAR(m.t - m.t_prev, 0.025, 1e-9);
  EXPECT_EQ(m.displacement(), Eigen::Vector2d(1, 2));
  EXPECT_EQ(m.displacementCovariance()(0, 0), 0.25);

  nav_msgs::Odometry o;
  o.pose.pose.orientation.w = 2;  // not a unit quaternion
  EXPECT_FALSE(toCameraOdometry(o).valid());
  o.pose.pose.orientation.w = 1;
  o.twist.twist.linear.x = 0.01;
  EXPECT_TRUE(toCameraOdometry(o).valid());

  surface_motion::SurfaceMotionOutput out;
  out.status = surface_motion::MotionStatus::kNoDepth;
  out.message = "why";
  out.velocity.surface_velocity = Vec3(1, 2, 3);  // not to be published
  const hapi_msgs::SurfaceMotion msg = toMessage(out, ros::Time(1), "imaging_optical_frame");
  EXPECT_EQ(msg.status, hapi_msgs::SurfaceMotion::STATUS_NO_DEPTH);
  EXPECT_EQ(msg.status_message, "why");
  EXPECT_EQ(msg.surface_velocity.x, 0.0);
  EXPECT_EQ(toMarker(msg, 0.002).action, visualization_msgs::Marker::DELETE);
}

}  // namespace
}  // namespace ros_glue
}  // namespace hapi_eskf
