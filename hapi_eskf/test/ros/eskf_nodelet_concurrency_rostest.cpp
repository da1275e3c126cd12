// rostest of EskfNodelet with every thread busy at once
// (eskf_nodelet_concurrency.test): a publisher thread streams synthetic
// landmarks (20 Hz) and gyro samples (200 Hz) while this thread calls
// ~reset, ~save_map, ~save_trajectory and ~load_map (a missing file) in
// turn and the map timer runs.
// Every call must answer, every reset must be acknowledged by the worker,
// and the filter must run again after the last reset, without filter
// errors. Under ThreadSanitizer (tools/sanitize.sh tsan) the same run checks
// the locking of the callbacks, the worker, the services and the timers.
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <hapi_msgs/LoadMap.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_srvs/Trigger.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

std::mutex mu;
std::size_t n_odom = 0;
std::map<std::string, std::string> diag;

void onOdom(const nav_msgs::Odometry::ConstPtr&) {
  std::lock_guard<std::mutex> lk(mu);
  ++n_odom;
}
void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  for (const auto& s : m->status)
    if (s.name.find("eskf") != std::string::npos)
      for (const auto& kv : s.values) diag[kv.key] = kv.value;
}
std::size_t numOdom() {
  std::lock_guard<std::mutex> lk(mu);
  return n_odom;
}
double diagValue(const std::string& key) {
  std::lock_guard<std::mutex> lk(mu);
  const auto it = diag.find(key);
  return it == diag.end() ? -1.0 : std::stod(it->second);
}
using hapi_eskf_test::waitFor;

// Landmarks and gyro samples of the synthetic scene on the wall clock, from
// its own thread, until stopped.
void stream(std::atomic<bool>* stop) {
  ros::NodeHandle nh;
  ros::Publisher lm = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 10);
  ros::Publisher imu = nh.advertise<sensor_msgs::Imu>("/imu/data", 400);
  hapi_eskf_test::SyntheticScene scene;
  const ros::Time t0 = ros::Time::now();
  for (int i = 0; !*stop; ++i) {
    const double t = 0.005 * i;
    sensor_msgs::Imu s;
    s.header.stamp = t0 + ros::Duration(t);
    s.header.frame_id = kFrame;
    s.angular_velocity.y = 0.08 * 0.8 * std::cos(0.8 * t);  // the scene's camera turns about y
    s.linear_acceleration.y = -9.81;
    s.orientation_covariance[0] = -1;
    imu.publish(s);
    if (i % 10 == 0) lm.publish(scene.frame(t, s.header.stamp, kFrame));
    ros::WallDuration(0.005).sleep();
  }
}

TEST(EskfNodeletConcurrency, ResetAndSaveWhileFramesAndImuArrive) {
  ros::NodeHandle nh;
  ros::Subscriber so = nh.subscribe("/eskf/odom", 1000, onOdom);
  ros::Subscriber sd = nh.subscribe("/diagnostics", 100, onDiag);
  ros::ServiceClient reset = nh.serviceClient<std_srvs::Trigger>("/eskf/reset");
  ros::ServiceClient save_map = nh.serviceClient<std_srvs::Trigger>("/eskf/save_map");
  ros::ServiceClient save_traj = nh.serviceClient<std_srvs::Trigger>("/eskf/save_trajectory");
  ros::ServiceClient load_map = nh.serviceClient<hapi_msgs::LoadMap>("/eskf/load_map");
  ASSERT_TRUE(reset.waitForExistence(ros::Duration(30.0)));
  ASSERT_TRUE(save_map.waitForExistence(ros::Duration(10.0)));
  ASSERT_TRUE(save_traj.waitForExistence(ros::Duration(10.0)));
  ASSERT_TRUE(load_map.waitForExistence(ros::Duration(10.0)));

  std::atomic<bool> stop{false};
  std::thread publisher(stream, &stop);
  ASSERT_TRUE(waitFor([] { return numOdom() > 20; }, 30.0)) << "no odometry from the streamed frames";

  int resets_acknowledged = 0, saves_answered = 0, loads_refused = 0;
  for (int round = 0; round < 6; ++round) {
    std_srvs::Trigger t;
    if (save_map.call(t)) ++saves_answered;
    if (save_traj.call(t)) ++saves_answered;
    hapi_msgs::LoadMap missing;  // a refused load: read and counted beside the worker and diagnostics
    missing.request.path = "/nonexistent/map.hmap";
    if (load_map.call(missing) && !missing.response.success) ++loads_refused;
    ros::WallDuration(0.15).sleep();
    ASSERT_TRUE(reset.call(t));
    if (t.response.success) ++resets_acknowledged;
    ros::WallDuration(0.25).sleep();
  }
  // After the last reset the filter starts again from the next frames.
  const std::size_t n0 = numOdom();
  EXPECT_TRUE(waitFor([&] { return numOdom() > n0 + 20; }, 20.0)) << "odometry did not resume after the resets";
  EXPECT_TRUE(waitFor([] { return diagValue("imu_samples_used") > 0; }, 5.0));
  EXPECT_EQ(loads_refused, 6);
  stop = true;
  publisher.join();
  std::printf("[eskf concurrency rostest] %d/6 resets acknowledged, %d/12 saves answered, %zu odometry messages, "
              "imu used %.0f, frames dropped %.0f\n",
              resets_acknowledged, saves_answered, numOdom(), diagValue("imu_samples_used"),
              diagValue("frames_dropped"));
  EXPECT_EQ(resets_acknowledged, 6);
  EXPECT_EQ(saves_answered, 12);
  EXPECT_GE(diagValue("resets"), 6.0);
  EXPECT_EQ(diagValue("filter_errors"), 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_concurrency");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
