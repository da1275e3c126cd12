// SurfaceMotionNodelet through ROS (surface_motion_nodelet.test): without TF
// to the imaging camera the output says NO_EXTRINSIC, without a map
// NO_DEPTH; with odometry of a still camera, a plane map and the flow of the
// skin sliding at 6 mm/s it says OK with that velocity, and the service
// returns the smoothed motion. Flows in a wrong frame, out of order or with
// NaN are counted on /diagnostics and change nothing.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <hapi_msgs/GetSurfaceMotion.h>
#include <hapi_msgs/ImageFlow.h>
#include <hapi_msgs/SurfaceMotion.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>

namespace {

constexpr double kFx = 500, kDepth = 0.3, kSpeed = 0.006;  // [px], [m], [m/s] along x

class SurfaceMotionNodeletTest : public ::testing::Test {
 protected:
  void SetUp() override {
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("/eskf/odom", 500);
    map_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/eskf/map", 1, true);
    flow_pub_ = nh_.advertise<hapi_msgs::ImageFlow>("/imaging_flow/flow", 50);
    info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("/imaging/camera_info", 1, true);
    sub_ = nh_.subscribe("/surface_motion/surface_motion", 1000, &SurfaceMotionNodeletTest::onMotion, this);
    diag_sub_ = nh_.subscribe("/diagnostics", 50, &SurfaceMotionNodeletTest::onDiagnostics, this);
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(20);
    while ((odom_pub_.getNumSubscribers() == 0 || flow_pub_.getNumSubscribers() == 0 ||
            sub_.getNumPublishers() == 0) && ros::WallTime::now() < until)
      ros::WallDuration(0.05).sleep();
  }

  void onMotion(const hapi_msgs::SurfaceMotion& m) {
    std::lock_guard<std::mutex> lk(mu_);
    received_.push_back(m);
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray& a) {
    std::lock_guard<std::mutex> lk(mu_);
    for (const auto& st : a.status)
      if (st.name.find("surface motion") != std::string::npos)
        for (const auto& kv : st.values) counters_[kv.key] = std::atoll(kv.value.c_str());
  }
  // Waits (5 s) until the diagnostics counter `key` reaches `at_least`.
  bool counterReaches(const std::string& key, long long at_least) {
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(5);
    while (ros::WallTime::now() < until) {
      {
        std::lock_guard<std::mutex> lk(mu_);
        if (counters_.count(key) && counters_[key] >= at_least) return true;
      }
      ros::WallDuration(0.05).sleep();
    }
    return false;
  }
  std::vector<hapi_msgs::SurfaceMotion> received() {
    std::lock_guard<std::mutex> lk(mu_);
    return received_;
  }
  // Waits until the output of `stamp` arrived (or 5 s).
  bool waitFor(const ros::Time& stamp) {
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(5);
    while (ros::WallTime::now() < until) {
      for (const auto& m : received())
        if (m.header.stamp == stamp) return true;
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }

  void publishOdom(const ros::Time& t, const std::string& child) {
    nav_msgs::Odometry o;
    o.header.stamp = t;
    o.header.frame_id = "map";
    o.child_frame_id = child;
    o.pose.pose.orientation.w = 1;
    odom_pub_.publish(o);
  }
  void publishInfoAndTf() {
    sensor_msgs::CameraInfo c;
    c.header.frame_id = "imaging_optical_frame";
    c.width = 640;
    c.height = 480;
    c.K = {kFx, 0, 319.5, 0, kFx, 239.5, 0, 0, 1};
    info_pub_.publish(c);
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "stereo_left_optical_frame";
    t.child_frame_id = "imaging_optical_frame";
    t.transform.rotation.w = 1;
    tf_.sendTransform(t);
  }
  void publishMap() {
    sensor_msgs::PointCloud2 cloud;
    cloud.header.frame_id = "map";
    sensor_msgs::PointCloud2Modifier mod(cloud);
    mod.setPointCloud2FieldsByString(1, "xyz");
    mod.resize(17 * 13);
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    for (int i = -8; i <= 8; ++i)
      for (int j = -6; j <= 6; ++j, ++x, ++y, ++z) {
        *x = 0.01f * i;
        *y = 0.01f * j;
        *z = static_cast<float>(kDepth);
      }
    map_pub_.publish(cloud);
  }

  ros::NodeHandle nh_;
  ros::Publisher odom_pub_, map_pub_, flow_pub_, info_pub_;
  ros::Subscriber sub_, diag_sub_;
  std::map<std::string, long long> counters_;
  tf2_ros::StaticTransformBroadcaster tf_;
  std::mutex mu_;
  std::vector<hapi_msgs::SurfaceMotion> received_;
};

TEST_F(SurfaceMotionNodeletTest, StatusesThenTheSkinsVelocity) {
  const ros::Time t0(1000.0);
  // 1. An odometry frame with no TF to the imaging camera: NO_EXTRINSIC.
  publishInfoAndTf();
  publishOdom(t0, "unknown_frame");
  ASSERT_TRUE(waitFor(t0));
  EXPECT_EQ(received().back().status, hapi_msgs::SurfaceMotion::STATUS_NO_EXTRINSIC);
  EXPECT_FALSE(received().back().status_message.empty());

  // 2. With TF and CameraInfo but no map: NO_DEPTH, and no made-up value.
  ros::Time t = t0;
  for (int k = 0; k < 40; ++k) {
    t += ros::Duration(0.005);
    publishOdom(t, "stereo_left_optical_frame");
    ros::WallDuration(0.002).sleep();
  }
  ASSERT_TRUE(waitFor(t));
  EXPECT_EQ(received().back().status, hapi_msgs::SurfaceMotion::STATUS_NO_DEPTH);
  EXPECT_EQ(received().back().speed, 0.0);

  // 3. The map, then 2 s of odometry (still) and 40 Hz flow of the skin
  // sliding at kSpeed along x: px per frame = fx * v / depth / 40.
  publishMap();
  ros::WallDuration(0.3).sleep();
  const ros::Time t_map = t;
  for (int k = 1; k <= 400; ++k) {
    t += ros::Duration(0.005);
    publishOdom(t, "stereo_left_optical_frame");
    if (k % 5 == 0) {
      hapi_msgs::ImageFlow f;
      f.header.stamp = t;
      f.header.frame_id = "imaging_optical_frame";
      f.previous_stamp = t - ros::Duration(0.025);
      f.u = 319.5;
      f.v = 239.5;
      f.affine[0] = kFx * kSpeed * 0.025 / kDepth;
      for (int i = 0; i < 6; ++i) f.affine_covariance[7 * i] = 4e-4;
      f.inliers = f.tracked = 30;
      flow_pub_.publish(f);
    }
    ros::WallDuration(0.002).sleep();
  }
  ASSERT_TRUE(waitFor(t));
  int ok = 0, fused = 0;
  for (const auto& m : received()) {
    if (m.header.stamp <= t_map + ros::Duration(1.0)) continue;
    EXPECT_EQ(m.status, hapi_msgs::SurfaceMotion::STATUS_OK) << m.status_message;
    EXPECT_EQ(m.header.frame_id, "imaging_optical_frame");
    EXPECT_NEAR(m.surface_velocity.x, 1000 * kSpeed, 0.5);  // mm/s
    EXPECT_NEAR(m.surface_velocity.y, 0.0, 0.5);
    EXPECT_NEAR(m.point.z, kDepth, 1e-3);
    EXPECT_NEAR(m.normal.z, -1.0, 1e-3);
    EXPECT_NEAR(m.image_velocity[0], kFx * kSpeed / kDepth / 40, 0.02);  // px/frame
    ++ok;
    fused += m.flow_fused;
  }
  EXPECT_GT(ok, 150);
  EXPECT_GT(fused, 30);
  EXPECT_TRUE(counterReaches("flows fused", 30));

  // 4. Bad flows: a wrong frame, one out of order, one with NaN. Counted;
  // the output stays OK with the same value.
  hapi_msgs::ImageFlow bad;
  bad.header.stamp = t - ros::Duration(0.5);  // before the last flow: out of order
  bad.header.frame_id = "imaging_optical_frame";
  bad.previous_stamp = bad.header.stamp - ros::Duration(0.025);
  bad.u = 319.5;
  bad.v = 239.5;
  bad.affine[0] = 50;
  for (int i = 0; i < 6; ++i) bad.affine_covariance[7 * i] = 4e-4;
  flow_pub_.publish(bad);
  bad.header.stamp = t + ros::Duration(0.025);
  bad.previous_stamp = t;
  bad.header.frame_id = "some_other_camera";
  flow_pub_.publish(bad);
  bad.header.frame_id = "imaging_optical_frame";
  bad.affine[0] = std::nan("");
  flow_pub_.publish(bad);
  EXPECT_TRUE(counterReaches("flows out of order", 1));
  EXPECT_TRUE(counterReaches("flows wrong frame", 1));
  EXPECT_TRUE(counterReaches("flows invalid", 1));
  t += ros::Duration(0.03);
  publishOdom(t, "stereo_left_optical_frame");
  ASSERT_TRUE(waitFor(t));
  EXPECT_EQ(received().back().status, hapi_msgs::SurfaceMotion::STATUS_OK);
  EXPECT_NEAR(received().back().surface_velocity.x, 1000 * kSpeed, 0.5);

  // 5. The smoothed motion over the last second.
  hapi_msgs::GetSurfaceMotion srv;
  srv.request.start = t - ros::Duration(1.0);
  srv.request.end = t;
  ASSERT_TRUE(ros::service::call("/surface_motion/smoothed_motion", srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_GT(srv.response.motion.size(), 150u);
  for (const auto& m : srv.response.motion) EXPECT_NEAR(m.surface_velocity.x, 1000 * kSpeed, 0.5);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "surface_motion_nodelet_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int r = RUN_ALL_TESTS();
  ros::shutdown();
  return r;
}
