// rostest (eskf_nodelet_map.test): the sessions of hapi_eskf/EskfNodelet
// (docs/DESIGN.md "Map file") on synthetic frames, in one run:
//  1. ~map_file names a file that does not exist: the node starts without a
//     map, /diagnostics counts the failure and says "no map loaded";
//  2. session 1 maps the scene; ~save_map writes a map file that reads back
//     with the published stereo calibration;
//  3. ~load_map with a missing and with a corrupt file: an error response
//     naming the fault, counted, and the node keeps running;
//  4. ~load_map with the saved map, then the camera somewhere else in the
//     scene (no hint): no odometry until /diagnostics says relocalised, then
//     odometry in session 1's frame;
//  5. the map loaded again and frames of another scene: never relocalised,
//     no odometry.
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include "hapi_eskf/map_file/map_reader.hpp"

#include <hapi_msgs/LoadMap.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

using hapi_eskf_test::NodeletObserver;
using hapi_eskf_test::waitFor;

NodeletObserver* obs = nullptr;
ros::Publisher* pub = nullptr;
ros::Time t0;
double t_stamp = 0.0;  // stamp of the last frame since t0: always forward (no time-jump reset)

std::string diagText(const std::string& key) {
  std::lock_guard<std::mutex> lk(obs->mu);
  const auto it = obs->diag.find(key);
  return it == obs->diag.end() ? std::string() : it->second;
}

// A diagnostics report newer than now, so that its values reflect what was done before.
bool freshDiagnostics() {
  int seen = 0;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    seen = obs->diags;
  }
  return waitFor([&] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return obs->diags > seen + 1;
  }, 5.0);
}

void publish(hapi_eskf_test::SyntheticScene& scene, double t_scene) {
  t_stamp += 0.05;
  pub->publish(scene.frame(t_scene, t0 + ros::Duration(t_stamp), kFrame));
}

// Publishes frames of `scene` at scene times t_scene, t_scene + 0.05, ...
// and waits for the odometry of each (lockstep: nothing is dropped however
// slow the machine). False when one brought no odometry within 10 s.
bool publishLockstep(hapi_eskf_test::SyntheticScene& scene, double t_scene, int frames) {
  for (int i = 0; i < frames; ++i) {
    const std::size_t n = obs->numOdom();
    publish(scene, t_scene + 0.05 * i);
    if (!waitFor([&] { return obs->numOdom() > n; }, 10.0)) return false;
  }
  return true;
}

hapi_msgs::LoadMap loadMap(const std::string& path) {
  hapi_msgs::LoadMap srv;
  srv.request.path = path;
  EXPECT_TRUE(ros::service::call("/eskf/load_map", srv));
  return srv;
}

Eigen::Vector3d odomPosition(const nav_msgs::Odometry& o) {
  return {o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z};
}

hapi_eskf_test::SyntheticScene* scene = nullptr;
std::string saved_map;

}  // namespace

TEST(EskfNodeletMap, BadMapFileAtStartUpLeavesTheNodeRunningWithoutAMap) {
  ASSERT_TRUE(waitFor([] { return pub->getNumSubscribers() > 0; }, 30.0)) << "nodelet not subscribed";
  ASSERT_TRUE(freshDiagnostics());
  EXPECT_EQ(obs->diagCount("map_load_failures"), 1);
  EXPECT_NE(diagText("last_map_load_failure").find("io:"), std::string::npos) << diagText("last_map_load_failure");
  EXPECT_EQ(diagText("relocalisation"), "no map loaded");
  EXPECT_EQ(diagText("map_file"), "none");
  std::lock_guard<std::mutex> lk(obs->mu);
  const diagnostic_msgs::DiagnosticStatus& filter = obs->statuses["eskf: filter"];
  EXPECT_EQ(filter.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(filter.message.find("map not loaded: '/nonexistent/hapi_map.hmap': io:"), std::string::npos)
      << filter.message;
}

TEST(EskfNodeletMap, SaveMapWritesAMapFileWithTheCalibration) {
  ASSERT_TRUE(publishLockstep(*scene, 0.0, 60)) << "session 1 published no odometry";
  std_srvs::Trigger srv;
  ASSERT_TRUE(ros::service::call("/eskf/save_map", srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  saved_map = srv.response.message;
  hapi_eskf::map_file::MapData map;
  const hapi_eskf::map_file::MapError err = hapi_eskf::map_file::readMapFile(saved_map, {}, &map);
  ASSERT_FALSE(err) << err.message;
  EXPECT_GT(map.landmarks.size(), 50u);
  EXPECT_EQ(map.map_frame, "map");
  EXPECT_EQ(map.camera_frame, kFrame);
  EXPECT_EQ(map.calibration.width, 640u);
  EXPECT_DOUBLE_EQ(map.calibration.fx, hapi_eskf_test::kCameraInfoFocal);
  EXPECT_NEAR(map.calibration.baseline, hapi_eskf_test::kCameraInfoBaseline, 1e-12);
  EXPECT_FALSE(map.calibration.has_imu);
  EXPECT_EQ(map.gravity_direction.norm(), 0.0);  // constant velocity: no gravity
}

TEST(EskfNodeletMap, LoadMapRefusesMissingAndCorruptFiles) {
  const hapi_msgs::LoadMap missing = loadMap("/nonexistent/other.hmap");
  EXPECT_FALSE(missing.response.success);
  EXPECT_EQ(missing.response.message.rfind("io:", 0), 0u) << missing.response.message;
  EXPECT_EQ(missing.response.landmarks, 0u);

  const std::string corrupt = "/tmp/hapi_corrupt_" + std::to_string(::getpid()) + ".hmap";
  std::ofstream(corrupt) << "this is not a map file, it is long enough for a header";
  const hapi_msgs::LoadMap bad = loadMap(corrupt);
  std::remove(corrupt.c_str());
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.message.rfind("magic:", 0), 0u) << bad.response.message;

  ASSERT_TRUE(freshDiagnostics());
  EXPECT_EQ(obs->diagCount("map_load_failures"), 3);
  EXPECT_EQ(diagText("relocalisation"), "no map loaded");
  // Still tracking: the failed loads changed nothing.
  EXPECT_TRUE(publishLockstep(*scene, 3.0, 3));
}

TEST(EskfNodeletMap, RelocalisesInTheLoadedMapWithoutAHint) {
  ASSERT_FALSE(saved_map.empty());
  const hapi_msgs::LoadMap ok = loadMap(saved_map);
  ASSERT_TRUE(ok.response.success) << ok.response.message;
  EXPECT_GT(ok.response.landmarks, 50u);
  // Session 2: the camera 1 s into session 1's trajectory (0.25 m and a
  // turn away from the map's origin); the filter starts at the origin.
  const double t_start = 1.0;
  const std::size_t odom_before = obs->numOdom();
  const long held_before = obs->diagCount("frames_relocalising");
  int frames = 0;
  std::string state;
  while (frames < 40) {
    publish(*scene, t_start + 0.05 * frames++);
    if (!freshDiagnostics()) continue;
    state = diagText("relocalisation");
    if (state.rfind("relocalised in the loaded map at ", 0) == 0) break;
    EXPECT_EQ(state, "waiting for the loaded map");
  }
  ASSERT_EQ(state.rfind("relocalised in the loaded map at ", 0), 0u) << "not relocalised within 40 frames: " << state;
  const double relocalised_at = std::stod(state.substr(std::string("relocalised in the loaded map at ").size()));
  std::printf("relocalised after %d frames (%ld held back)\n", frames,
              obs->diagCount("frames_relocalising") - held_before);
  // No odometry while the filter waited: every output from the
  // relocalising frame on.
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    ASSERT_GT(obs->odoms.size(), odom_before);
    for (std::size_t i = odom_before; i < obs->odoms.size(); ++i)
      EXPECT_GE(obs->odoms[i].header.stamp.toSec(), relocalised_at - 1e-3) << "odometry while waiting for the map";
  }
  ASSERT_TRUE(publishLockstep(*scene, t_start + 0.05 * frames, 20));
  nav_msgs::Odometry last;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    last = obs->odoms.back();
  }
  EXPECT_EQ(last.header.frame_id, "map");
  const double t_last = t_start + 0.05 * (frames + 19);
  const Eigen::Vector3d truth = (scene->pose(0.0).inverse() * scene->pose(t_last)).translation();
  std::printf("20 frames after relocalising: %.1f mm from the truth in session 1's frame\n",
              1e3 * (odomPosition(last) - truth).norm());
  EXPECT_LT((odomPosition(last) - truth).norm(), 0.05)
      << "estimate " << odomPosition(last).transpose() << " truth in session 1's frame " << truth.transpose();
  EXPECT_EQ(obs->diagCount("map_loads"), 1);
}

TEST(EskfNodeletMap, AnotherSceneNeverRelocalisesInTheMap) {
  const hapi_msgs::LoadMap ok = loadMap(saved_map);
  ASSERT_TRUE(ok.response.success) << ok.response.message;
  hapi_eskf_test::SyntheticScene other(400, 7);
  const std::size_t odom_before = obs->numOdom();
  ASSERT_TRUE(freshDiagnostics());
  const long held_before = obs->diagCount("frames_relocalising");
  for (int i = 0; i < 40; ++i) {
    publish(other, 0.05 * i);
    ros::WallDuration(0.03).sleep();
  }
  ASSERT_TRUE(freshDiagnostics());
  EXPECT_EQ(diagText("relocalisation"), "waiting for the loaded map");
  EXPECT_EQ(obs->numOdom(), odom_before) << "odometry from frames of another scene";
  EXPECT_GE(obs->diagCount("frames_relocalising") - held_before, 20) << "frames held back";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_map");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  NodeletObserver o(nh);
  obs = &o;
  ros::Publisher p = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 100);
  pub = &p;
  const auto camera_info = hapi_eskf_test::latchStereoCameraInfo(nh, kFrame);
  hapi_eskf_test::SyntheticScene sc;
  scene = &sc;
  t0 = ros::Time::now();
  waitFor([&] { return o.connected(); }, 30.0);
  ros::service::waitForService("/eskf/load_map", 30000);
  const int rc = RUN_ALL_TESTS();
  if (!saved_map.empty()) {
    std::remove(saved_map.c_str());
    std::remove((saved_map.substr(0, saved_map.size() - 4) + "ply").c_str());
  }
  spinner.stop();
  return rc;
}
