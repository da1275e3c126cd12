// rostest of hapi_eskf/EskfNodelet (loaded by eskf_nodelet.test as /eskf in a
// manager). The tests run in order on one nodelet instance:
//  1. synthetic frames -> odom, TF, map, path grow; pose follows the truth;
//     a burst faster than the worker: every frame processed or counted dropped;
//  2. fuzz: malformed messages interleaved with good ones -> node alive, each
//     rejection counted in /diagnostics, no output (pose unchanged) for them;
//  3. ~save_map writes a map file with a valid PLY beside it, ~save_trajectory a TUM file; ~refine (the
//     ES-EKF's recorded run, batch refined) writes a PLY and a TUM file;
//  4. a stamp jumping backwards (bag loop) resets filter and path;
//  5. ~reset empties the map.
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

using hapi_eskf_test::NodeletObserver;
using hapi_eskf_test::waitFor;

NodeletObserver* obs = nullptr;
ros::Publisher* pub = nullptr;
hapi_eskf_test::SyntheticScene* scene = nullptr;
ros::Time t0;
tf2_ros::Buffer* tf_buffer = nullptr;
double t_scene = 0.0;  // scene time of the last good frame

// Publishes the next good frame (20 Hz scene time). Lockstep (default): waits
// until the nodelet has published its odometry, so no frame is dropped however
// slow the machine is (speed is measured in benchmarks, not here). Returns
// false when no output came within 10 s.
bool publishGood(bool lockstep = true) {
  t_scene += 0.05;
  const std::size_t n = obs->numOdom();
  pub->publish(scene->frame(t_scene, t0 + ros::Duration(t_scene), kFrame));
  if (!lockstep) return true;
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::ok() && ros::WallTime::now() < end && obs->numOdom() == n) ros::WallDuration(0.002).sleep();
  return obs->numOdom() > n;
}

Eigen::Vector3d odomPosition(const nav_msgs::Odometry& o) {
  return {o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z};
}

// Truth of the camera position in the filter's world (= first camera frame).
Eigen::Vector3d truthInFirstCamera(double t, double t_first) {
  return (scene->pose(t_first).inverse() * scene->pose(t)).translation();
}

}  // namespace

TEST(EskfNodelet, ProcessesSyntheticFrames) {
  ASSERT_TRUE(waitFor([] { return pub->getNumSubscribers() > 0; }, 30.0)) << "nodelet not subscribed";
  const double t_first = t_scene + 0.05;
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(publishGood()) << "no odometry for frame " << i;
  EXPECT_EQ(obs->numOdom(), 60u);

  // Odometry: REP-105 frames, child = camera, finite covariance.
  nav_msgs::Odometry last;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    last = obs->odoms.back();
  }
  EXPECT_EQ(last.header.frame_id, "map");
  EXPECT_EQ(last.child_frame_id, kFrame);
  EXPECT_GT(last.pose.covariance[0], 0.0);
  EXPECT_GT(last.pose.covariance[35], 0.0);
  // The estimate follows the truth (world = first camera; 3 m of travel).
  const double t_last = (last.header.stamp - t0).toSec();
  const Eigen::Vector3d err = odomPosition(last) - truthInFirstCamera(t_last, t_first);
  EXPECT_LT(err.norm(), 0.05) << "estimate " << odomPosition(last).transpose() << " truth "
                              << truthInFirstCamera(t_last, t_first).transpose();

  // Twist in the child (camera) frame with its covariance: the scene moves at
  // d/dt (0.25 t, 0.05 sin 1.5t, 0.1 t) in the scene world; in the camera
  // frame that is R(t)^T times it.
  {
    const Eigen::Vector3d v_world(0.25, 0.075 * std::cos(1.5 * t_last), 0.1);
    const Eigen::Vector3d v_cam = scene->pose(t_last).linear().transpose() * v_world;
    const auto& tw = last.twist.twist.linear;
    EXPECT_LT((Eigen::Vector3d(tw.x, tw.y, tw.z) - v_cam).norm(), 0.1)
        << "twist " << tw.x << " " << tw.y << " " << tw.z << " truth " << v_cam.transpose();
    for (int i = 0; i < 6; ++i) {
      EXPECT_GT(last.twist.covariance[i * 6 + i], 0.0) << i;
      for (int j = 0; j < 6; ++j) EXPECT_DOUBLE_EQ(last.twist.covariance[i * 6 + j], last.twist.covariance[j * 6 + i]);
    }
  }

  // TF map -> camera.
  std::string tf_err;
  EXPECT_TRUE(tf_buffer->canTransform("map", kFrame, ros::Time(0), ros::Duration(3.0), &tf_err)) << tf_err;

  // Map non-empty with the documented fields; path grows.
  ASSERT_TRUE(waitFor([] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return obs->maps > 0 && obs->map.width > 20;
  }, 5.0));
  EXPECT_TRUE(waitFor([] { return obs->lastPathSize() == 60u; }, 5.0));
  std::lock_guard<std::mutex> lk(obs->mu);
  EXPECT_EQ(obs->map.header.frame_id, "map");
  ASSERT_EQ(obs->map.fields.size(), 6u);
  EXPECT_EQ(obs->map.fields[4].name, "sigma");
  ASSERT_GE(obs->path_sizes.size(), 10u);
  EXPECT_GT(obs->path_sizes.back(), obs->path_sizes.front());
  EXPECT_EQ(obs->path_sizes.back(), 60u);
  std::printf("[eskf rostest] diagnostics: t_total_ms %s landmarks %s\n", obs->diag["t_total_ms"].c_str(),
              obs->diag["landmarks"].c_str());
}

// The map cloud: documented fields (x y z rgb sigma FLOAT32, id UINT32),
// per-point content (finite, sigma > 0, the scene's colours, unique ids) and
// the configured ~map_publish_rate (5 Hz in eskf_nodelet.test) as an upper
// bound: never faster however fast frames come, at least one map per second.
TEST(EskfNodelet, MapCloudFieldsContentAndConfiguredRate) {
  sensor_msgs::PointCloud2 cloud;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    cloud = obs->map;
  }
  const std::vector<std::pair<std::string, std::uint8_t>> expected = {
      {"x", sensor_msgs::PointField::FLOAT32},   {"y", sensor_msgs::PointField::FLOAT32},
      {"z", sensor_msgs::PointField::FLOAT32},   {"rgb", sensor_msgs::PointField::FLOAT32},
      {"sigma", sensor_msgs::PointField::FLOAT32}, {"id", sensor_msgs::PointField::UINT32}};
  ASSERT_EQ(cloud.fields.size(), expected.size());
  std::map<std::string, std::uint32_t> offset;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(cloud.fields[i].name, expected[i].first);
    EXPECT_EQ(cloud.fields[i].datatype, expected[i].second) << expected[i].first;
    EXPECT_EQ(cloud.fields[i].count, 1u);
    offset[cloud.fields[i].name] = cloud.fields[i].offset;
  }
  ASSERT_GT(cloud.width, 20u);
  ASSERT_EQ(cloud.data.size(), std::size_t(cloud.row_step) * cloud.height);
  std::set<std::uint32_t> ids;
  for (std::uint32_t i = 0; i < cloud.width; ++i) {
    const std::uint8_t* pt = &cloud.data[i * cloud.point_step];
    auto f32 = [&](const std::string& n) {
      float v;
      std::memcpy(&v, pt + offset[n], 4);
      return v;
    };
    std::uint32_t rgb, id;
    std::memcpy(&rgb, pt + offset["rgb"], 4);
    std::memcpy(&id, pt + offset["id"], 4);
    EXPECT_TRUE(std::isfinite(f32("x")) && std::isfinite(f32("y")) && std::isfinite(f32("z")));
    EXPECT_GT(f32("z"), 0.0f) << "landmarks lie in front of the first camera";
    EXPECT_TRUE(std::isfinite(f32("sigma")) && f32("sigma") > 0.0f && f32("sigma") < 0.5f) << f32("sigma");
    EXPECT_EQ(rgb & 0xffu, 128u) << "blue channel of the synthetic scene (0x00RRGGBB)";
    EXPECT_TRUE(ids.insert(id).second) << "duplicate id " << id;
  }

  // Frames as fast as they come for 2 s (no lockstep): maps at <= 5 Hz.
  const double dropped0 = obs->diagValue("frames_dropped");
  std::size_t maps0;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    maps0 = obs->map_times.size();
  }
  const ros::WallTime start = ros::WallTime::now();
  while ((ros::WallTime::now() - start).toSec() < 2.0) {
    publishGood(false);
    ros::WallDuration(0.01).sleep();
  }
  const double window = (ros::WallTime::now() - start).toSec();
  ros::WallDuration(0.1).sleep();
  std::size_t maps;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    maps = obs->map_times.size() - maps0;
  }
  std::printf("[eskf rostest] %zu maps in %.2f s of input at ~100 Hz (map_publish_rate 5 Hz)\n", maps, window);
  EXPECT_LE(maps, static_cast<std::size_t>(5.0 * window) + 2);
  EXPECT_GE(maps, 2u);
  // Diagnostics of the busy period: rates and per-stage timings are reported.
  EXPECT_GT(obs->diagValue("input_rate_hz"), 5.0);
  EXPECT_GT(obs->diagValue("processing_rate_hz"), 0.0);
  EXPECT_GT(obs->diagValue("output_rate_hz"), 0.0);
  EXPECT_GT(obs->diagValue("t_total_ms"), 0.0);
  EXPECT_GT(obs->diagValue("t_update_ms"), 0.0);
  // The callback never waits for the filter (GPU work stays on the worker):
  // when a frame takes longer than the input period, the surplus shows up as
  // counted mailbox drops, not as a blocked callback (whose ROS queue would
  // discard messages silently). eskf_nodelet.test makes every frame update
  // take >= 50 ms (~test_frame_delay), 5x the input period.
  EXPECT_GT(obs->diagValue("frames_dropped"), dropped0) << "slow worker but no counted drops";
  // Let the worker drain so the next tests start from an idle node.
  const double t_last = t_scene;
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return std::abs((obs->odoms.back().header.stamp - t0).toSec() - t_last) < 1e-6;
  }, 10.0));
}

// A burst faster than the worker: newest wins. Every accepted frame is either
// processed, counted as dropped, or counted as failed (nothing lost silently),
// and the last frame of the burst is always processed.
TEST(EskfNodelet, BurstIsAccountedAsProcessedOrDropped) {
  const double acc0 = obs->diagValue("frames_accepted");
  ASSERT_GE(acc0, 0.0);
  for (int i = 0; i < 15; ++i) publishGood(false);
  const double t_last = t_scene;
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return std::abs((obs->odoms.back().header.stamp - t0).toSec() - t_last) < 1e-6;
  }, 10.0)) << "the newest frame of the burst was not processed";
  auto balance = [] {
    return obs->diagValue("frames_processed") + obs->diagValue("frames_dropped") +
           obs->diagValue("frames_stale_after_reset") + obs->diagValue("frames_failed");
  };
  const bool balanced = waitFor([&] {
    return obs->diagValue("frames_accepted") > acc0 && obs->diagValue("frames_accepted") == balance();
  }, 5.0);
  EXPECT_TRUE(balanced) << "accepted " << obs->diagValue("frames_accepted") << " != processed+dropped+stale+failed "
                        << balance();
  std::printf("[eskf rostest] burst of 15: accepted %.0f, dropped so far %.0f\n",
              obs->diagValue("frames_accepted") - acc0, obs->diagValue("frames_dropped"));
}

TEST(EskfNodelet, MalformedMessagesAreRejectedAndCounted) {
  ASSERT_TRUE(publishGood());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<std::string, hapi_msgs::StereoLandmarks>> bad;
  auto make = [&](double dt) { return scene->frame(t_scene + dt, t0 + ros::Duration(t_scene + dt), kFrame); };
  {
    auto m = make(0.01);
    m.landmarks.at(3).position.x = nan;
    bad.emplace_back("rejected_non_finite", m);
  }
  {
    auto m = make(0.01);
    m.landmarks.at(0).position_covariance = {1e-4, 0, 0, 0, -1e-4, 0, 0, 0, 1e-4};
    bad.emplace_back("rejected_bad_covariance", m);
  }
  {
    auto m = make(0.01);
    m.descriptors.resize(m.descriptors.size() - 5);
    bad.emplace_back("rejected_descriptor_size", m);
  }
  {
    auto m = make(0.01);
    m.descriptor_length = 61;
    m.descriptors.assign(m.landmarks.size() * 61, 7);
    bad.emplace_back("rejected_descriptor_length", m);
  }
  {
    auto m = make(0.01);
    m.descriptor_type = hapi_msgs::StereoLandmarks::DESCRIPTOR_AKAZE;
    bad.emplace_back("rejected_descriptor_type", m);
  }
  {
    auto m = make(0.01);
    const auto one = m.landmarks.at(0);
    m.landmarks.assign(5000, one);  // huge count (> max_measurements_per_msg)
    m.descriptors.assign(5000 * 32, 1);
    bad.emplace_back("rejected_too_many_measurements", m);
  }
  {
    auto m = make(0.01);
    m.header.frame_id = "some_other_frame";
    bad.emplace_back("rejected_frame_id", m);
  }
  {
    auto m = make(0.01);
    m.landmarks.at(2).id = m.landmarks.at(1).id;
    bad.emplace_back("rejected_duplicate_id", m);
  }
  {
    auto m = make(-0.2);  // older than the last accepted frame, but no bag loop
    bad.emplace_back("rejected_stamp_backwards", m);
  }
  std::map<std::string, double> before;
  for (const auto& b : bad) before[b.first] = std::max(0.0, obs->diagValue(b.first));

  // Bad-only burst: no output at all, i.e. the state is untouched.
  const std::size_t n0 = obs->numOdom();
  nav_msgs::Odometry ref;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    ref = obs->odoms.back();
  }
  for (const auto& b : bad) {
    pub->publish(b.second);
    ros::WallDuration(0.03).sleep();
  }
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(obs->numOdom(), n0) << "a malformed message produced an output";

  // Interleaved: every good frame still produces exactly one output.
  for (int rep = 0; rep < 2; ++rep) {
    for (const auto& b : bad) {
      EXPECT_TRUE(publishGood());
      auto m = b.second;
      m.header.stamp = t0 + ros::Duration(t_scene + (b.first == "rejected_stamp_backwards" ? -0.2 : 0.01));
      pub->publish(m);
      ros::WallDuration(0.03).sleep();
    }
  }
  EXPECT_TRUE(publishGood());
  // Exactly one output per good frame, none for the malformed ones.
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(obs->numOdom(), n0 + 2 * bad.size() + 1);
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    // The first output after the bad burst continues the trajectory smoothly.
    const double step = (odomPosition(obs->odoms[n0]) - odomPosition(ref)).norm();
    EXPECT_LT(step, 0.1);
  }
  // Every reason counted 3 times (burst + 2 interleaved rounds).
  const bool counted = waitFor([&] {
    for (const auto& b : bad)
      if (obs->diagValue(b.first) < before[b.first] + 3) return false;
    return true;
  }, 5.0);
  EXPECT_TRUE(counted);
  for (const auto& b : bad) EXPECT_GE(obs->diagValue(b.first), before[b.first] + 3) << b.first;
}

TEST(EskfNodelet, SaveServicesWritePlyAndTum) {
  std_srvs::Trigger srv;
  ASSERT_TRUE(ros::service::waitForService("/eskf/save_map", 5000));
  ASSERT_TRUE(ros::service::call("/eskf/save_map", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  // The map file (eskf_nodelet_map_rostest.cpp reads and loads it) and the
  // PLY of its points beside it.
  const std::string& map_path = srv.response.message;
  ASSERT_EQ(map_path.substr(map_path.size() - 5), ".hmap") << map_path;
  {
    std::ifstream f(map_path.substr(0, map_path.size() - 4) + "ply");
    ASSERT_TRUE(f.good()) << srv.response.message;
    std::string line;
    int vertices = -1, rows = 0;
    while (std::getline(f, line) && line != "end_header")
      if (line.rfind("element vertex ", 0) == 0) vertices = std::stoi(line.substr(15));
    while (std::getline(f, line)) {
      std::istringstream ss(line);
      double v[7];
      for (double& x : v) ASSERT_TRUE(ss >> x) << line;
      EXPECT_GT(v[2], 0.0) << "landmarks lie in front of the first camera";
      EXPECT_GT(v[6], 0.0);
      ++rows;
    }
    EXPECT_GT(vertices, 20);
    EXPECT_EQ(rows, vertices);
  }
  ASSERT_TRUE(ros::service::call("/eskf/save_trajectory", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  std::ifstream f(srv.response.message);
  ASSERT_TRUE(f.good());
  std::string line;
  int rows = 0;
  double prev_t = -1;
  double last_row[8] = {0};
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(ss >> x) << line;
    EXPECT_GT(v[0], prev_t);
    prev_t = v[0];
    EXPECT_NEAR(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7], 1.0, 1e-6);
    std::copy(v, v + 8, last_row);
    ++rows;
  }
  // The last row is the last published odometry (t x y z qx qy qz qw).
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    const auto& o = obs->odoms.back();
    EXPECT_NEAR(last_row[0], o.header.stamp.toSec(), 1e-6);
    EXPECT_NEAR(last_row[1], o.pose.pose.position.x, 1e-6);
    EXPECT_NEAR(last_row[2], o.pose.pose.position.y, 1e-6);
    EXPECT_NEAR(last_row[3], o.pose.pose.position.z, 1e-6);
    EXPECT_NEAR(std::abs(last_row[4] * o.pose.pose.orientation.x + last_row[5] * o.pose.pose.orientation.y +
                         last_row[6] * o.pose.pose.orientation.z + last_row[7] * o.pose.pose.orientation.w),
                1.0, 1e-6);
  }
  EXPECT_GE(static_cast<std::size_t>(rows), obs->numOdom() * 8 / 10);  // drops allowed, no losses in the file
}

// ~refine with the ES-EKF live: its recorded run, refined, as PLY + TUM (the
// formats of ~save_map / ~save_trajectory) in ~output_dir.
TEST(EskfNodelet, RefineServiceWritesRefinedMapAndTrajectory) {
  std_srvs::Trigger srv;
  ASSERT_TRUE(ros::service::waitForService("/eskf/refine", 5000));
  ASSERT_TRUE(ros::service::call("/eskf/refine", srv));
  if (srv.response.message.find("not built") != std::string::npos) GTEST_SKIP() << srv.response.message;
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  std::istringstream paths(srv.response.message);
  std::string ply, tum;
  ASSERT_TRUE(paths >> ply >> tum) << srv.response.message;
  std::ifstream p(ply), t(tum);
  ASSERT_TRUE(p.good()) << ply;
  ASSERT_TRUE(t.good()) << tum;
  std::string line;
  int vertices = -1, rows = 0, poses = 0;
  while (std::getline(p, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoi(line.substr(15));
  while (std::getline(p, line)) {
    std::istringstream ss(line);
    double v[7];
    for (double& x : v) ASSERT_TRUE(ss >> x) << line;
    EXPECT_GT(v[2], 0.0) << "landmarks lie in front of the first camera";
    ++rows;
  }
  EXPECT_GT(vertices, 20);
  EXPECT_EQ(rows, vertices);
  while (std::getline(t, line)) poses += !line.empty() && line[0] != '#';
  EXPECT_GE(static_cast<std::size_t>(poses), obs->numOdom() * 8 / 10);
}

TEST(EskfNodelet, TimeJumpBackwardsResetsFilterAndPath) {
  const double jumps0 = std::max(0.0, obs->diagValue("time_jumps"));
  const double resets0 = std::max(0.0, obs->diagValue("resets"));
  // Bag loop: scene time continues, stamps restart 100 s earlier (our own
  // TF buffer would reject the "old" transforms, like any TF user after a loop).
  tf_buffer->clear();
  t0 -= ros::Duration(100.0);
  const double t_first = t_scene + 0.05;
  const std::size_t n0 = obs->numOdom();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(publishGood());
  EXPECT_EQ(obs->numOdom(), n0 + 20);
  EXPECT_TRUE(waitFor([&] { return obs->diagValue("time_jumps") >= jumps0 + 1; }, 5.0));
  // The jump is counted where the frame arrives, the reset where the worker
  // takes it: a diagnostics message in between has the one, not yet the other.
  EXPECT_TRUE(waitFor([&] { return obs->diagValue("resets") >= resets0 + 1; }, 5.0));
  // Path restarted: exactly the 20 frames of the new timeline.
  EXPECT_TRUE(waitFor([] { return obs->lastPathSize() == 20u; }, 5.0));
  std::lock_guard<std::mutex> lk(obs->mu);
  EXPECT_EQ(obs->path_sizes.back(), 20u);
  // World re-anchored at the first camera after the jump.
  const auto& o = obs->odoms.back();
  const Eigen::Vector3d truth = truthInFirstCamera((o.header.stamp - t0).toSec(), t_first);
  EXPECT_LT((odomPosition(o) - truth).norm(), 0.05);
}

TEST(EskfNodelet, ResetServiceClearsMap) {
  std_srvs::Trigger srv;
  ASSERT_TRUE(ros::service::call("/eskf/reset", srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_TRUE(waitFor([] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return obs->map.width == 0;
  }, 3.0));
  const std::size_t n0 = obs->numOdom();
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(publishGood());
  EXPECT_EQ(obs->numOdom(), n0 + 5);
  std::lock_guard<std::mutex> lk(obs->mu);
  EXPECT_LT(odomPosition(obs->odoms.back()).norm(), 0.3);  // restarted near the origin
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  NodeletObserver o(nh);
  obs = &o;
  ros::Publisher p = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 100);
  pub = &p;
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  tf_buffer = &buffer;
  hapi_eskf_test::SyntheticScene sc;
  scene = &sc;
  // The stereo calibration a saved map records.
  const auto camera_info = hapi_eskf_test::latchStereoCameraInfo(nh, kFrame);
  t0 = ros::Time::now();
  // Give our subscriptions time to connect before anything is published.
  waitFor([&] { return o.connected(); }, 30.0);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
