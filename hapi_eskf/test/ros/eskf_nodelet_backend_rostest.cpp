// rostest of hapi_eskf/EskfNodelet running one of the SLAM back ends that
// are not the default ES-EKF; the .test file picks it (~backend_algorithm of
// the nodelet) and tells this test what to expect through its private
// parameters:
//   ~expected_storage  the "backend" value /diagnostics must report
//                      (SlamBackend::storage(): "seif", "graph-cpu", ...)
//   ~frames            synthetic frames to publish (default 60)
//   ~max_position_error  bound on |p - p_true| [m] at EVERY odometry message
//                      (a diverging back end fails at the first frame it
//                      leaves the bound, not only at the end)
//   ~max_rotation_error  the same for the rotation [rad]
// Synthetic frames in lockstep (synthetic_frames.hpp) -> odometry that
// follows the truth with a finite covariance, a map with per-point sigma,
// and /diagnostics with every frame processed and no filter error.
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace {

const std::string kFrame = "stereo_left_optical_frame";

struct Expectations {
  std::string storage;
  int frames = 60;
  double max_position_error = 0.05;
  double max_rotation_error = 0.05;
};

using hapi_eskf_test::NodeletObserver;
using hapi_eskf_test::waitFor;

NodeletObserver* obs = nullptr;
ros::Publisher* pub = nullptr;
hapi_eskf_test::SyntheticScene* scene = nullptr;
Expectations expect;
ros::Time t0;
const double kFirstFrame = 0.05;  // [s] since t0: the first frame defines the map frame
const double kFramePeriod = 0.05;

// The true camera pose in the map frame (the first camera) at `stamp`.
Eigen::Isometry3d truthInMap(const ros::Time& stamp) {
  return scene->pose(kFirstFrame).inverse() * scene->pose((stamp - t0).toSec());
}

}  // namespace

TEST(EskfNodeletBackend, FollowsTheTruthAndPublishesTheMap) {
  ASSERT_TRUE(waitFor([] { return pub->getNumSubscribers() > 0; }, 30.0)) << "nodelet not subscribed";
  double t = 0.0;
  for (int i = 0; i < expect.frames; ++i) {
    t += kFramePeriod;
    const std::size_t n = obs->numOdom();
    pub->publish(scene->frame(t, t0 + ros::Duration(t), kFrame));
    ASSERT_TRUE(waitFor([&] { return obs->numOdom() > n; }, 10.0)) << "no odometry for frame " << i;
  }
  std::vector<nav_msgs::Odometry> odoms;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    odoms = obs->odoms;
  }
  ASSERT_GE(static_cast<int>(odoms.size()), expect.frames);
  // Bounded at every step (never diverges), not only at the end.
  double worst_p = 0.0, worst_r = 0.0;
  for (const nav_msgs::Odometry& o : odoms) {
    const Eigen::Isometry3d truth = truthInMap(o.header.stamp);
    const Eigen::Vector3d est(o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z);
    const Eigen::Quaterniond q(o.pose.pose.orientation.w, o.pose.pose.orientation.x, o.pose.pose.orientation.y,
                               o.pose.pose.orientation.z);
    ASSERT_TRUE(est.allFinite() && q.coeffs().allFinite()) << "non-finite pose at " << o.header.stamp;
    const double e_p = (est - truth.translation()).norm();
    const double e_r = q.normalized().angularDistance(Eigen::Quaterniond(truth.linear()));
    worst_p = std::max(worst_p, e_p);
    worst_r = std::max(worst_r, e_r);
    EXPECT_LT(e_p, expect.max_position_error) << "at t=" << (o.header.stamp - t0).toSec() << " estimate "
                                              << est.transpose() << " truth " << truth.translation().transpose();
    EXPECT_LT(e_r, expect.max_rotation_error) << "at t=" << (o.header.stamp - t0).toSec();
  }
  RecordProperty("worst_position_error_mm", static_cast<int>(std::lround(worst_p * 1e3)));
  const nav_msgs::Odometry& last = odoms.back();
  EXPECT_EQ(last.header.frame_id, "map");
  EXPECT_EQ(last.child_frame_id, kFrame);
  for (int i = 0; i < 6; ++i)
    EXPECT_TRUE(std::isfinite(last.pose.covariance[i * 7]) && last.pose.covariance[i * 7] > 0.0) << i;

  // Diagnostics: every frame processed, none failed, no filter error.
  ASSERT_TRUE(waitFor([] { return obs->diagCount("frames_processed") >= expect.frames; }, 5.0))
      << "frames_processed " << obs->diagCount("frames_processed") << " < " << expect.frames;
  ASSERT_TRUE(waitFor([] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return obs->map.width > 20 && obs->diag.count("backend") > 0;
  }, 5.0));
  std::lock_guard<std::mutex> lk(obs->mu);
  EXPECT_EQ(obs->diag["backend"], expect.storage);
  EXPECT_EQ(obs->diag["filter_errors"], "0") << obs->diag["last_filter_error"];
  EXPECT_EQ(obs->diag["frames_failed"], "0");
  EXPECT_EQ(obs->diag["backend_faults"], "0");
  sensor_msgs::PointCloud2ConstIterator<float> sigma(obs->map, "sigma");
  for (; sigma != sigma.end(); ++sigma) EXPECT_TRUE(std::isfinite(*sigma) && *sigma > 0.0f);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_backend");
  ros::NodeHandle nh, pnh("~");
  if (!pnh.getParam("expected_storage", expect.storage)) {
    std::fprintf(stderr, "~expected_storage is required (the .test file names the back end)\n");
    return 2;
  }
  pnh.param("frames", expect.frames, expect.frames);
  pnh.param("max_position_error", expect.max_position_error, expect.max_position_error);
  pnh.param("max_rotation_error", expect.max_rotation_error, expect.max_rotation_error);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  NodeletObserver o(nh);
  obs = &o;
  ros::Publisher p = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 100);
  pub = &p;
  hapi_eskf_test::SyntheticScene sc;
  scene = &sc;
  t0 = ros::Time::now();
  waitFor([&] { return o.connected(); }, 30.0);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
