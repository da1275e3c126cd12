// What the hapi_eskf rostests share: waiting for a condition on the wall
// clock, and an observer of one EskfNodelet's outputs (odometry, path, map
// and the values of its /diagnostics status) that subscribes to them itself.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstddef>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace hapi_eskf_test {

// True as soon as p() holds, false when it still does not after timeout_s
// (wall clock: the tests run with and without /clock); polls every poll_s.
template <typename Pred>
bool waitFor(Pred p, double timeout_s, double poll_s = 0.005) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (p()) return true;
    ros::WallDuration(poll_s).sleep();
  }
  return p();
}

// Every message of NS/odom and NS/path, the latest NS/map with the arrival
// time of each, and the latest value of every key of the diagnostics
// statuses whose name contains "eskf". Members are read under `mu`.
struct NodeletObserver {
  std::mutex mu;
  std::vector<nav_msgs::Odometry> odoms;
  std::vector<std::size_t> path_sizes;
  sensor_msgs::PointCloud2 map;
  int maps = 0;
  std::vector<ros::WallTime> map_times;
  std::map<std::string, std::string> diag;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> statuses;  // the latest, by status name (values cleared)
  int diags = 0;

  explicit NodeletObserver(ros::NodeHandle& nh, const std::string& ns = "/eskf")
      : odom_sub_(nh.subscribe(ns + "/odom", 1000, &NodeletObserver::onOdom, this)),
        path_sub_(nh.subscribe(ns + "/path", 100, &NodeletObserver::onPath, this)),
        map_sub_(nh.subscribe(ns + "/map", 10, &NodeletObserver::onMap, this)),
        diag_sub_(nh.subscribe("/diagnostics", 100, &NodeletObserver::onDiag, this)) {}

  // The nodelet's odometry and diagnostics publishers are connected to us.
  bool connected() const { return odom_sub_.getNumPublishers() > 0 && diag_sub_.getNumPublishers() > 0; }

  std::size_t numOdom() {
    std::lock_guard<std::mutex> lk(mu);
    return odoms.size();
  }
  // Poses in the latest path message, 0 before the first. The path is a
  // topic of its own: a frame's path message may come after its odometry.
  std::size_t lastPathSize() {
    std::lock_guard<std::mutex> lk(mu);
    return path_sizes.empty() ? 0 : path_sizes.back();
  }
  // The latest value of a diagnostics key, -1 before the key was seen.
  double diagValue(const std::string& key) {
    std::lock_guard<std::mutex> lk(mu);
    const auto it = diag.find(key);
    return it == diag.end() ? -1.0 : std::stod(it->second);
  }
  long diagCount(const std::string& key) {
    std::lock_guard<std::mutex> lk(mu);
    const auto it = diag.find(key);
    return it == diag.end() ? -1 : std::stol(it->second);
  }

 private:
  void onOdom(const nav_msgs::Odometry::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    odoms.push_back(*m);
  }
  void onPath(const nav_msgs::Path::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    path_sizes.push_back(m->poses.size());
  }
  void onMap(const sensor_msgs::PointCloud2::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    map = *m;
    ++maps;
    map_times.push_back(ros::WallTime::now());
  }
  void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    for (const auto& s : m->status) {
      if (s.name.find("eskf") == std::string::npos) continue;
      for (const auto& kv : s.values) diag[kv.key] = kv.value;
      statuses[s.name] = s;
      statuses[s.name].values.clear();
      ++diags;
    }
  }

  // Declared last: unsubscribed before the data above is destroyed.
  ros::Subscriber odom_sub_, path_sub_, map_sub_, diag_sub_;
};

}  // namespace hapi_eskf_test
