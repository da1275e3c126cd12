// rostest of EskfNodelet with ~base_frame and ~use_imu (eskf_nodelet_imu_base.test).
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <gtest/gtest.h>

#include <map>
#include <mutex>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

std::mutex mu;
std::vector<nav_msgs::Odometry> odoms;
std::map<std::string, std::string> diag;

void onOdom(const nav_msgs::Odometry::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  odoms.push_back(*m);
}
void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  for (const auto& s : m->status)
    if (s.name.find("eskf") != std::string::npos)
      for (const auto& kv : s.values) diag[kv.key] = kv.value;
}
std::size_t numOdom() {
  std::lock_guard<std::mutex> lk(mu);
  return odoms.size();
}
double diagValue(const std::string& k) {
  std::lock_guard<std::mutex> lk(mu);
  return diag.count(k) ? std::stod(diag[k]) : -1.0;
}
template <typename P>
bool waitFor(P p, double s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(s);
  while (ros::ok() && ros::WallTime::now() < end && !p()) ros::WallDuration(0.005).sleep();
  return p();
}

// Mounting used in the launch file (base_link -> camera, imu_link = base axes).
Eigen::Isometry3d baseToCamera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1, 0, 0.5);
  return T;
}

}  // namespace

TEST(EskfNodeletImuBase, MapAnchoredAtFirstBasePoseWithGyroPrediction) {
  ros::NodeHandle nh;
  ros::Subscriber s1 = nh.subscribe("/eskf/odom", 1000, onOdom);
  ros::Subscriber s2 = nh.subscribe("/diagnostics", 100, onDiag);
  ros::Publisher pub = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 10);
  ros::Publisher imu_pub = nh.advertise<sensor_msgs::Imu>("/imu/data", 200);
  tf2_ros::StaticTransformBroadcaster static_tf;
  {
    std::vector<geometry_msgs::TransformStamped> mounts(2);
    const Eigen::Isometry3d T = baseToCamera();
    const Eigen::Quaterniond q(T.linear());
    mounts[0].header.stamp = ros::Time::now();
    mounts[0].header.frame_id = "base_link";
    mounts[0].child_frame_id = kFrame;
    mounts[0].transform.translation.x = T.translation().x();
    mounts[0].transform.translation.y = T.translation().y();
    mounts[0].transform.translation.z = T.translation().z();
    mounts[0].transform.rotation.w = q.w();
    mounts[0].transform.rotation.x = q.x();
    mounts[0].transform.rotation.y = q.y();
    mounts[0].transform.rotation.z = q.z();
    mounts[1].header = mounts[0].header;
    mounts[1].child_frame_id = "imu_link";
    mounts[1].transform.translation.z = 0.3;
    mounts[1].transform.rotation.w = 1.0;
    static_tf.sendTransform(mounts);
  }
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  // Our own odom subscription must be connected too, or the first frame's
  // output is lost and the lockstep below waits for nothing.
  ASSERT_TRUE(waitFor([&] {
    return pub.getNumSubscribers() > 0 && imu_pub.getNumSubscribers() > 0 && s1.getNumPublishers() > 0;
  }, 30.0));
  ASSERT_TRUE(buffer.canTransform("base_link", kFrame, ros::Time(0), ros::Duration(5.0)));

  hapi_eskf_test::SyntheticScene scene;
  const ros::Time t0 = ros::Time::now();
  const Eigen::Matrix3d R_imu_cam = baseToCamera().linear();  // imu axes = base axes
  const double t_first = 0.05;
  for (int i = 1; i <= 50; ++i) {
    const double t = 0.05 * i;
    // 100 Hz gyro between the previous frame and this one: the body rate of
    // R(t) = RotY(0.08 sin 0.8t) is 0.064 cos(0.8t) about the camera's y axis.
    for (int k = 4; k >= 0; --k) {
      const double ti = t - 0.01 * k;
      sensor_msgs::Imu imu;
      imu.header.stamp = t0 + ros::Duration(ti);
      imu.header.frame_id = "imu_link";
      const Eigen::Vector3d w = R_imu_cam * Eigen::Vector3d(0, 0.064 * std::cos(0.8 * ti), 0);
      imu.angular_velocity.x = w.x();
      imu.angular_velocity.y = w.y();
      imu.angular_velocity.z = w.z();
      imu.orientation_covariance[0] = -1;
      imu_pub.publish(imu);
    }
    ros::WallDuration(0.01).sleep();
    const std::size_t n = numOdom();
    pub.publish(scene.frame(t, t0 + ros::Duration(t), kFrame));
    ASSERT_TRUE(waitFor([&] { return numOdom() > n; }, 10.0)) << "frame " << i;
  }
  nav_msgs::Odometry last;
  {
    std::lock_guard<std::mutex> lk(mu);
    last = odoms.back();
  }
  // odom is the camera pose in map = first base pose: T_map_cam = T_base_cam * T_c0_ct.
  const double t_last = (last.header.stamp - t0).toSec();
  const Eigen::Isometry3d truth = baseToCamera() * scene.pose(t_first).inverse() * scene.pose(t_last);
  const Eigen::Vector3d p(last.pose.pose.position.x, last.pose.pose.position.y, last.pose.pose.position.z);
  EXPECT_LT((p - truth.translation()).norm(), 0.05) << p.transpose() << " vs " << truth.translation().transpose();
  const Eigen::Quaterniond q(last.pose.pose.orientation.w, last.pose.pose.orientation.x,
                             last.pose.pose.orientation.y, last.pose.pose.orientation.z);
  EXPECT_LT(Eigen::AngleAxisd(q.toRotationMatrix().transpose() * truth.linear()).angle(), 0.02);

  // TF: map -> base_link is published (the camera keeps its base_link parent),
  // and map -> camera through it equals the odometry.
  std::string err;
  ASSERT_TRUE(buffer.canTransform("map", kFrame, last.header.stamp, ros::Duration(3.0), &err)) << err;
  const auto t = buffer.lookupTransform("map", kFrame, last.header.stamp);
  EXPECT_NEAR(t.transform.translation.x, p.x(), 1e-6);
  EXPECT_NEAR(t.transform.translation.z, p.z(), 1e-6);
  EXPECT_TRUE(buffer._frameExists("base_link"));

  // The gyro drove the prediction.
  EXPECT_TRUE(waitFor([] { return diagValue("imu_samples_used") > 100; }, 5.0)) << diagValue("imu_samples_used");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_imu_base");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
