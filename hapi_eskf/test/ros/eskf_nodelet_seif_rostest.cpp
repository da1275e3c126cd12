// rostest of hapi_eskf/EskfNodelet running the SEIF back end
// (eskf_nodelet_seif.test: ~backend_algorithm seif, 30 active landmarks):
// synthetic frames in lockstep -> odometry that follows the truth with a
// finite covariance, a map with per-point sigma, and /diagnostics naming the
// seif storage.
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

struct Observer {
  std::mutex mu;
  std::vector<nav_msgs::Odometry> odoms;
  sensor_msgs::PointCloud2 map;
  std::map<std::string, std::string> diag;

  void onOdom(const nav_msgs::Odometry::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    odoms.push_back(*m);
  }
  void onMap(const sensor_msgs::PointCloud2::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    map = *m;
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
};

template <typename Pred>
bool waitFor(Pred p, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (p()) return true;
    ros::WallDuration(0.02).sleep();
  }
  return p();
}

Observer* obs = nullptr;
ros::Publisher* pub = nullptr;
hapi_eskf_test::SyntheticScene* scene = nullptr;
ros::Time t0;

}  // namespace

TEST(EskfNodeletSeif, FollowsTheTruthAndPublishesTheMap) {
  ASSERT_TRUE(waitFor([] { return pub->getNumSubscribers() > 0; }, 30.0)) << "nodelet not subscribed";
  const int n_frames = 60;
  double t = 0.0;
  const double t_first = 0.05;
  for (int i = 0; i < n_frames; ++i) {
    t += 0.05;
    const std::size_t n = obs->numOdom();
    pub->publish(scene->frame(t, t0 + ros::Duration(t), kFrame));
    ASSERT_TRUE(waitFor([&] { return obs->numOdom() > n; }, 10.0)) << "no odometry for frame " << i;
  }
  nav_msgs::Odometry last;
  {
    std::lock_guard<std::mutex> lk(obs->mu);
    last = obs->odoms.back();
  }
  EXPECT_EQ(last.header.frame_id, "map");
  EXPECT_EQ(last.child_frame_id, kFrame);
  for (int i = 0; i < 6; ++i) EXPECT_GT(last.pose.covariance[i * 7], 0.0) << i;
  const double t_last = (last.header.stamp - t0).toSec();
  const Eigen::Vector3d truth = (scene->pose(t_first).inverse() * scene->pose(t_last)).translation();
  const Eigen::Vector3d est(last.pose.pose.position.x, last.pose.pose.position.y, last.pose.pose.position.z);
  EXPECT_LT((est - truth).norm(), 0.05) << "estimate " << est.transpose() << " truth " << truth.transpose();

  ASSERT_TRUE(waitFor([] {
    std::lock_guard<std::mutex> lk(obs->mu);
    return obs->map.width > 20 && obs->diag.count("backend") > 0;
  }, 5.0));
  std::lock_guard<std::mutex> lk(obs->mu);
  EXPECT_EQ(obs->diag["backend"], "seif");
  sensor_msgs::PointCloud2ConstIterator<float> sigma(obs->map, "sigma");
  for (; sigma != sigma.end(); ++sigma) EXPECT_TRUE(std::isfinite(*sigma) && *sigma > 0.0f);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_seif");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  Observer o;
  obs = &o;
  ros::Subscriber s1 = nh.subscribe("/eskf/odom", 1000, &Observer::onOdom, &o);
  ros::Subscriber s2 = nh.subscribe("/eskf/map", 10, &Observer::onMap, &o);
  ros::Subscriber s3 = nh.subscribe("/diagnostics", 100, &Observer::onDiag, &o);
  ros::Publisher p = nh.advertise<hapi_msgs::StereoLandmarks>("/eskf/landmarks", 100);
  pub = &p;
  hapi_eskf_test::SyntheticScene sc;
  scene = &sc;
  t0 = ros::Time::now();
  waitFor([&] { return s1.getNumPublishers() > 0 && s3.getNumPublishers() > 0; }, 30.0);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
