// Map snapshots, ~map and ~save_map of EskfNodelet (map_publisher.hpp says
// which thread calls what).
#include "hapi_eskf/ros/map_publisher.hpp"

#include "hapi_eskf/ros/export.hpp"

#include <ros/console.h>
#include <sensor_msgs/PointCloud2.h>

#include <chrono>
#include <utility>

namespace hapi_eskf {
namespace ros_glue {

MapPublisher::MapPublisher(const NodeletParams& params, ros::Publisher map_pub, std::string log_name)
    : world_frame_(params.world_frame),
      output_dir_(params.output_dir),
      period_(1.0 / params.map_publish_rate),
      log_name_(std::move(log_name)),
      map_pub_(std::move(map_pub)) {}

bool MapPublisher::snapshotDue() {
  return requested_.exchange(false) || (ros::WallTime::now() - last_snapshot_wall_).toSec() >= period_;
}

void MapPublisher::takeSnapshot(const std::function<std::vector<MapPoint>()>& read_map, const ros::Time& stamp) {
  last_snapshot_wall_ = ros::WallTime::now();
  auto pts = std::make_shared<const std::vector<MapPoint>>(read_map());
  {
    std::lock_guard<std::mutex> lk(mu_);
    snapshot_ = std::move(pts);
    snapshot_stamp_ = stamp;
    ++generation_;
  }
  cv_.notify_all();
}

void MapPublisher::publishLatest() {
  Snapshot snap;
  ros::Time stamp;
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (generation_ == published_generation_ || !snapshot_) return;
    published_generation_ = generation_;
    snap = snapshot_;
    stamp = snapshot_stamp_;
  }
  sensor_msgs::PointCloud2 cloud = toPointCloud2(*snap);
  cloud.header.stamp = stamp;
  cloud.header.frame_id = world_frame_;
  map_pub_.publish(cloud);
}

void MapPublisher::close() {
  {
    std::lock_guard<std::mutex> lk(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

bool MapPublisher::waitForSnapshot(std::uint64_t after, Snapshot* out) {
  requested_ = true;
  std::unique_lock<std::mutex> lk(mu_);
  cv_.wait_for(lk, std::chrono::seconds(2), [&] { return generation_ > after || closed_; });
  *out = snapshot_;
  return generation_ > after;
}

bool MapPublisher::save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::uint64_t gen;
  {
    std::lock_guard<std::mutex> lk(mu_);
    gen = generation_;
  }
  Snapshot snap;
  if (!waitForSnapshot(gen, &snap)) {
    res.success = false;
    res.message = "no fresh map snapshot from the worker within 2 s";
    return true;
  }
  const std::string path = timestampedPath(output_dir_, "hapi_map", "ply");
  const std::string err = writePly(path, snap ? *snap : std::vector<MapPoint>{});
  res.success = err.empty();
  res.message = res.success ? path : err;
  if (res.success)
    ROS_INFO_NAMED(log_name_, "saved %zu map points to %s", snap ? snap->size() : 0, path.c_str());
  else
    ROS_ERROR_NAMED(log_name_, "~save_map failed: %s", err.c_str());
  return true;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
