// rostest of EskfNodelet with ~base_frame and ~motion_model gyro (eskf_nodelet_imu_base.test).
// The tests run in order on one nodelet instance:
//  1. frames at 20 Hz with 100 Hz gyro in between: map anchored at the first
//     base pose, TF map -> base_link, the gyro drives the prediction;
//  2. frames at 10 Hz, gyro at 100 Hz: odometry (and TF) at the IMU rate, one
//     output per gyro sample with strictly increasing stamps, following the
//     truth between frames, twist = the gyro rate.
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <mutex>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

std::mutex mu;
std::vector<nav_msgs::Odometry> odoms;
std::vector<ros::WallTime> odom_arrivals;
std::size_t n_paths = 0;
ros::WallTime last_path_arrival;
std::map<std::string, std::string> diag;
std::map<std::string, std::string> diag_no_tf;  // the second nodelet (IMU frame without TF)

void onOdom(const nav_msgs::Odometry::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  odoms.push_back(*m);
  odom_arrivals.push_back(ros::WallTime::now());
}
void onPath(const nav_msgs::Path::ConstPtr&) {
  std::lock_guard<std::mutex> lk(mu);
  ++n_paths;
  last_path_arrival = ros::WallTime::now();
}
void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  for (const auto& s : m->status) {
    if (s.name.find("eskf_no_tf") != std::string::npos)
      for (const auto& kv : s.values) diag_no_tf[kv.key] = kv.value;
    else if (s.name.find("eskf") != std::string::npos)
      for (const auto& kv : s.values) diag[kv.key] = kv.value;
  }
}
std::size_t numOdom() {
  std::lock_guard<std::mutex> lk(mu);
  return odoms.size();
}
std::size_t numPaths() {
  std::lock_guard<std::mutex> lk(mu);
  return n_paths;
}
// The newest odometry; an empty message (stamp 0) before the first one, so
// that waiting for a stamp simply keeps waiting (back() of an empty vector is
// undefined: ThreadSanitizer's slower run caught a wait that began before any
// output had arrived).
nav_msgs::Odometry lastOdom() {
  std::lock_guard<std::mutex> lk(mu);
  return odoms.empty() ? nav_msgs::Odometry() : odoms.back();
}
double diagValue(const std::string& k) {
  std::lock_guard<std::mutex> lk(mu);
  return diag.count(k) ? std::stod(diag[k]) : -1.0;
}
using hapi_eskf_test::waitFor;

// Mounting used in the launch file (base_link -> camera, imu_link = base axes).
Eigen::Isometry3d baseToCamera() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1, 0, 0.5);
  return T;
}

// Shared by the tests (created in main after ros::init).
struct Rig {
  ros::NodeHandle nh;
  ros::Subscriber odom_sub = nh.subscribe("/eskf/odom", 5000, onOdom);
  ros::Subscriber path_sub = nh.subscribe("/eskf/path", 100, onPath);
  ros::Subscriber diag_sub = nh.subscribe("/diagnostics", 100, onDiag);
  ros::Publisher pub = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 10);
  ros::Publisher imu_pub = nh.advertise<sensor_msgs::Imu>("/imu/data", 200);
  tf2_ros::StaticTransformBroadcaster static_tf;
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener{buffer};
  hapi_eskf_test::SyntheticScene scene;
  ros::Time t0;
  const double t_first = 0.05;  // scene time of the first frame (the filter's world)

  // Gyro sample of the scene motion at scene time t, in imu_link axes: the
  // body rate of R(t) = RotY(0.08 sin 0.8t) is 0.064 cos(0.8t) about the
  // camera's y axis.
  void publishImu(double t) {
    sensor_msgs::Imu imu;
    imu.header.stamp = t0 + ros::Duration(t);
    imu.header.frame_id = "imu_link";
    const Eigen::Vector3d w = baseToCamera().linear() * Eigen::Vector3d(0, 0.064 * std::cos(0.8 * t), 0);
    imu.angular_velocity.x = w.x();
    imu.angular_velocity.y = w.y();
    imu.angular_velocity.z = w.z();
    imu.orientation_covariance[0] = -1;
    imu_pub.publish(imu);
  }
  // Truth of the camera in map (= first base pose): T_base_cam * T_c0_ct.
  Eigen::Isometry3d truth(double t) const { return baseToCamera() * scene.pose(t_first).inverse() * scene.pose(t); }
};
Rig* rig = nullptr;

Eigen::Vector3d position(const nav_msgs::Odometry& o) {
  return {o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z};
}
Eigen::Quaterniond orientation(const nav_msgs::Odometry& o) {
  return {o.pose.pose.orientation.w, o.pose.pose.orientation.x, o.pose.pose.orientation.y,
          o.pose.pose.orientation.z};
}

}  // namespace

TEST(EskfNodeletImuBase, MapAnchoredAtFirstBasePoseWithGyroPrediction) {
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
    rig->static_tf.sendTransform(mounts);
  }
  // Our own odom/path subscriptions must be connected too, or the first
  // frame's output is lost and the lockstep below waits for nothing.
  ASSERT_TRUE(waitFor([&] {
    return rig->pub.getNumSubscribers() > 0 && rig->imu_pub.getNumSubscribers() > 0 &&
           rig->odom_sub.getNumPublishers() > 0 && rig->path_sub.getNumPublishers() > 0;
  }, 30.0));
  ASSERT_TRUE(rig->buffer.canTransform("base_link", kFrame, ros::Time(0), ros::Duration(5.0)));

  rig->t0 = ros::Time::now();
  for (int i = 1; i <= 50; ++i) {
    const double t = 0.05 * i;
    for (int k = 4; k >= 0; --k) rig->publishImu(t - 0.01 * k);  // 100 Hz up to this frame
    ros::WallDuration(0.01).sleep();
    const std::size_t n = numPaths();
    rig->pub.publish(rig->scene.frame(t, rig->t0 + ros::Duration(t), kFrame));
    ASSERT_TRUE(waitFor([&] { return numPaths() > n; }, 10.0)) << "frame " << i;
  }
  ASSERT_TRUE(waitFor([&] { return (lastOdom().header.stamp - rig->t0).toSec() > 2.5 - 1e-6; }, 5.0));
  const nav_msgs::Odometry last = lastOdom();
  // odom is the camera pose in map = first base pose.
  const double t_last = (last.header.stamp - rig->t0).toSec();
  const Eigen::Isometry3d truth = rig->truth(t_last);
  const Eigen::Vector3d p = position(last);
  EXPECT_LT((p - truth.translation()).norm(), 0.05) << p.transpose() << " vs " << truth.translation().transpose();
  EXPECT_LT(Eigen::AngleAxisd(orientation(last).toRotationMatrix().transpose() * truth.linear()).angle(), 0.02);

  // TF: map -> base_link is published (the camera keeps its base_link parent),
  // and map -> camera through it equals the odometry.
  std::string err;
  ASSERT_TRUE(rig->buffer.canTransform("map", kFrame, last.header.stamp, ros::Duration(3.0), &err)) << err;
  const auto t = rig->buffer.lookupTransform("map", kFrame, last.header.stamp);
  EXPECT_NEAR(t.transform.translation.x, p.x(), 1e-6);
  EXPECT_NEAR(t.transform.translation.z, p.z(), 1e-6);
  EXPECT_TRUE(rig->buffer._frameExists("base_link"));

  // The gyro drove the prediction.
  EXPECT_TRUE(waitFor([] { return diagValue("imu_samples_used") > 100; }, 5.0)) << diagValue("imu_samples_used");
  // Between the first two frames the velocity was the start's guess: the
  // samples there (0.06-0.10 s) gave no output (pose_propagator.hpp).
  EXPECT_TRUE(waitFor([] { return diagValue("imu_rate_outputs_held") >= 4; }, 5.0))
      << diagValue("imu_rate_outputs_held");
}

// 10 Hz frames, 100 Hz gyro published ahead of the frames (as a real IMU is,
// the front end adding latency): every gyro sample yields one odometry (and
// TF) output with its stamp, i.e. the output rate is the IMU rate (>= 40 Hz
// required), counted in stamp time so the machine's speed does not matter.
TEST(EskfNodeletImuBase, OdometryAndTfAtImuRate) {
  const double t_start = 2.5;  // where the first test stopped
  const int n_frames = 20;
  std::vector<ros::Time> imu_stamps;
  double max_pos_err = 0.0, max_rot_err = 0.0, max_gyro_err = 0.0;
  for (int f = 1; f <= n_frames; ++f) {
    const double t_frame = t_start + 0.1 * f;
    for (int k = 9; k >= 0; --k) {
      const double ti = t_frame - 0.01 * k;
      const ros::Time stamp = rig->t0 + ros::Duration(ti);
      rig->publishImu(ti);
      imu_stamps.push_back(stamp);
      ASSERT_TRUE(waitFor([&] { return lastOdom().header.stamp >= stamp; }, 10.0)) << "no output for IMU at " << ti;
      const nav_msgs::Odometry o = lastOdom();
      ASSERT_EQ(o.header.stamp, stamp);  // exactly one output, at the sample's stamp
      const Eigen::Isometry3d truth = rig->truth(ti);
      max_pos_err = std::max(max_pos_err, (position(o) - truth.translation()).norm());
      max_rot_err = std::max(
          max_rot_err, Eigen::AngleAxisd(orientation(o).toRotationMatrix().transpose() * truth.linear()).angle());
      // Twist in the camera frame: the angular part is the gyro rate, less
      // the gyro model's bias estimate, rotated into the camera (imu_link ->
      // camera through TF). The simulated gyro has no bias; the frames of
      // the first 2.5 s settle the estimate well below 1e-3 rad/s.
      max_gyro_err = std::max(max_gyro_err, std::abs(o.twist.twist.angular.y - 0.064 * std::cos(0.8 * ti)));
      EXPECT_GT(o.twist.covariance[35], 0.0);
    }
    const std::size_t n = numPaths();
    rig->pub.publish(rig->scene.frame(t_frame, rig->t0 + ros::Duration(t_frame), kFrame));
    ASSERT_TRUE(waitFor([&] { return numPaths() > n; }, 10.0)) << "frame at " << t_frame;
  }
  // Outputs in the stamp span of this test: one per gyro sample, strictly increasing.
  std::vector<double> out;
  {
    std::lock_guard<std::mutex> lk(mu);
    for (const auto& o : odoms)
      if (o.header.stamp >= imu_stamps.front()) out.push_back(o.header.stamp.toSec());
  }
  ASSERT_EQ(out.size(), imu_stamps.size());
  for (std::size_t i = 1; i < out.size(); ++i) ASSERT_GT(out[i], out[i - 1]);
  const double rate = (out.size() - 1) / (out.back() - out.front());
  EXPECT_GE(rate, 40.0);
  std::printf("[eskf imu rostest] %zu outputs, %.1f Hz (stamp time) with 10 Hz frames; max err %.4f m %.4f rad, "
              "gyro %.2e rad/s\n", out.size(), rate, max_pos_err, max_rot_err, max_gyro_err);
  EXPECT_LT(max_pos_err, 0.05);
  EXPECT_LT(max_rot_err, 0.02);
  EXPECT_LT(max_gyro_err, 1e-3);

  // TF between frames: map -> camera at an IMU stamp equals that output.
  const ros::Time mid = imu_stamps[imu_stamps.size() - 5];
  std::string err;
  ASSERT_TRUE(rig->buffer.canTransform("map", kFrame, mid, ros::Duration(3.0), &err)) << err;
  nav_msgs::Odometry at_mid;
  {
    std::lock_guard<std::mutex> lk(mu);
    for (const auto& o : odoms)
      if (o.header.stamp == mid) at_mid = o;
  }
  const auto tf = rig->buffer.lookupTransform("map", kFrame, mid);
  EXPECT_NEAR(tf.transform.translation.x, at_mid.pose.pose.position.x, 1e-6);
  EXPECT_NEAR(tf.transform.translation.y, at_mid.pose.pose.position.y, 1e-6);
  EXPECT_NEAR(tf.transform.translation.z, at_mid.pose.pose.position.z, 1e-6);
  EXPECT_TRUE(waitFor([] { return diagValue("imu_rate_outputs") >= 200; }, 5.0)) << diagValue("imu_rate_outputs");
}

// The IMU-rate outputs come from the IMU callback, not the worker: while a
// frame is being processed they keep flowing. eskf_nodelet_imu_base.test
// makes every frame update take >= 100 ms (~test_frame_delay), long enough
// for the order of arrival to mean something on any machine.
TEST(EskfNodeletImuBase, ImuOutputsDoNotWaitForTheFrameUpdate) {
  const double t_frame = 2.5 + 0.1 * 21;  // after the previous test's frames
  for (int k = 9; k >= 0; --k) {
    const double ti = t_frame - 0.01 * k;
    rig->publishImu(ti);
    const ros::Time stamp = rig->t0 + ros::Duration(ti);
    ASSERT_TRUE(waitFor([&] { return lastOdom().header.stamp >= stamp; }, 10.0));
  }
  const std::size_t n_path = numPaths(), n_odom = numOdom();
  rig->pub.publish(rig->scene.frame(t_frame, rig->t0 + ros::Duration(t_frame), kFrame));
  ros::WallDuration(0.002).sleep();  // the frame is in the worker's hands
  for (int k = 1; k <= 10; ++k) rig->publishImu(t_frame + 0.01 * k);
  ASSERT_TRUE(waitFor([&] { return numPaths() > n_path && numOdom() >= n_odom + 10; }, 10.0));
  int before = 0;
  ros::WallTime path_at;
  {
    std::lock_guard<std::mutex> lk(mu);
    path_at = last_path_arrival;
    for (std::size_t i = n_odom; i < odom_arrivals.size(); ++i) before += odom_arrivals[i] < path_at;
  }
  ASSERT_TRUE(waitFor([] { return diagValue("t_total_ms") > 0.0; }, 5.0));
  const double t_total = diagValue("t_total_ms");
  std::printf("[eskf imu rostest] %d of 10 IMU outputs arrived before the frame update finished (frame %.1f ms)\n",
              before, t_total);
  EXPECT_GE(before, 5);
}

// Bad IMU samples (NaN rate, a stamp not newer than the previous sample) are
// dropped and counted; they produce no output and do not move the pose.
TEST(EskfNodeletImuBase, BadImuSamplesAreDroppedAndCounted) {
  ASSERT_TRUE(waitFor([] { return diagValue("imu_samples_dropped") >= 0.0; }, 5.0));
  const double dropped0 = diagValue("imu_samples_dropped");
  const nav_msgs::Odometry before = lastOdom();
  const std::size_t n0 = numOdom();
  const double t_last = (before.header.stamp - rig->t0).toSec();
  sensor_msgs::Imu nan_imu;
  nan_imu.header.stamp = rig->t0 + ros::Duration(t_last + 0.01);
  nan_imu.header.frame_id = "imu_link";
  nan_imu.angular_velocity.x = std::numeric_limits<double>::quiet_NaN();
  rig->imu_pub.publish(nan_imu);
  rig->publishImu(t_last - 0.005);  // older than the last sample, not a time jump
  ASSERT_TRUE(waitFor([&] { return diagValue("imu_samples_dropped") >= dropped0 + 2; }, 5.0))
      << diagValue("imu_samples_dropped") << " vs " << dropped0;
  EXPECT_EQ(numOdom(), n0);
  // A good sample afterwards is used, continuing from the unchanged pose.
  rig->publishImu(t_last + 0.02);
  const ros::Time good = rig->t0 + ros::Duration(t_last + 0.02);
  ASSERT_TRUE(waitFor([&] { return lastOdom().header.stamp == good; }, 5.0));
  const nav_msgs::Odometry after = lastOdom();
  EXPECT_LT((position(after) - position(before)).norm(), 0.02);
  EXPECT_LT((position(after) - rig->truth(t_last + 0.02).translation()).norm(), 0.05);
}

double diagKey(const std::map<std::string, std::string>& d, const std::string& key) {
  std::lock_guard<std::mutex> lk(mu);
  const auto it = d.find(key);
  return it == d.end() ? -1.0 : std::stod(it->second);
}

// Each kind of bad IMU input has its own counter on /diagnostics; none of
// them produces an output or moves the pose. A gap is reported and bridged.
TEST(EskfNodeletImuBase, EachBadImuInputHasItsCounter) {
  const char* keys[] = {"imu_dropped_invalid", "imu_dropped_saturated", "imu_dropped_far_from_frames", "imu_gaps"};
  std::map<std::string, double> before_count;
  for (const char* k : keys) {
    ASSERT_TRUE(waitFor([&] { return diagKey(diag, k) >= 0.0; }, 5.0)) << k;
    before_count[k] = diagKey(diag, k);
  }
  const nav_msgs::Odometry before = lastOdom();
  const std::size_t n0 = numOdom();
  const double t_last = (before.header.stamp - rig->t0).toSec();
  auto sample = [&](double t) {
    sensor_msgs::Imu m;
    m.header.stamp = rig->t0 + ros::Duration(t);
    m.header.frame_id = "imu_link";
    m.linear_acceleration.y = -9.81;
    return m;
  };
  sensor_msgs::Imu bad = sample(t_last + 0.01);
  bad.linear_acceleration.z = std::numeric_limits<double>::infinity();  // non-finite specific force
  rig->imu_pub.publish(bad);
  bad = sample(t_last + 0.011);
  bad.angular_velocity.x = 50.0;  // beyond ~imu_gyro_limit: saturated
  rig->imu_pub.publish(bad);
  rig->imu_pub.publish(sample(t_last + 5.0));  // far from the newest image stamp (~imu_max_frame_offset)
  ASSERT_TRUE(waitFor(
      [&] { return diagKey(diag, "imu_dropped_far_from_frames") >= before_count["imu_dropped_far_from_frames"] + 1; },
      5.0));
  EXPECT_GE(diagKey(diag, "imu_dropped_invalid"), before_count["imu_dropped_invalid"] + 1);
  EXPECT_GE(diagKey(diag, "imu_dropped_saturated"), before_count["imu_dropped_saturated"] + 1);
  EXPECT_EQ(numOdom(), n0);
  // A gap of 0.2 s (> ~imu_max_gap): counted, the sample after it is used.
  rig->publishImu(t_last + 0.2);
  const ros::Time good = rig->t0 + ros::Duration(t_last + 0.2);
  ASSERT_TRUE(waitFor([&] { return lastOdom().header.stamp == good; }, 5.0));
  EXPECT_TRUE(waitFor([&] { return diagKey(diag, "imu_gaps") >= before_count["imu_gaps"] + 1; }, 5.0))
      << diagKey(diag, "imu_gaps");
  EXPECT_LT((position(lastOdom()) - rig->truth(t_last + 0.2).translation()).norm(), 0.05);
}

// An IMU whose frame has no TF to the camera: every sample is dropped and
// counted (imu_dropped_no_extrinsic), the filter runs on as if without IMU.
TEST(EskfNodeletImuBase, ImuWithoutExtrinsicIsDroppedAndCounted) {
  ros::NodeHandle nh;
  ros::Publisher lm = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf_no_tf/landmarks", 10);
  ros::Publisher imu = nh.advertise<sensor_msgs::Imu>("/imu/no_tf", 100);
  ASSERT_TRUE(waitFor([&] { return lm.getNumSubscribers() > 0 && imu.getNumSubscribers() > 0; }, 10.0));
  const double t = 100.0;
  lm.publish(rig->scene.frame(t, rig->t0 + ros::Duration(t), kFrame));
  ros::WallDuration(0.3).sleep();
  for (int k = 1; k <= 20; ++k) {
    sensor_msgs::Imu m;
    m.header.stamp = rig->t0 + ros::Duration(t + 0.005 * k);
    m.header.frame_id = "imu_without_tf";
    m.linear_acceleration.y = -9.81;
    imu.publish(m);
  }
  ASSERT_TRUE(waitFor([&] { return diagKey(diag_no_tf, "imu_dropped_no_extrinsic") >= 20; }, 5.0))
      << diagKey(diag_no_tf, "imu_dropped_no_extrinsic");
  EXPECT_EQ(diagKey(diag_no_tf, "imu_samples_used"), 0.0);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_imu_base");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  int rc;
  {
    Rig r;
    rig = &r;
    rc = RUN_ALL_TESTS();
    rig = nullptr;
  }
  spinner.stop();
  return rc;
}
