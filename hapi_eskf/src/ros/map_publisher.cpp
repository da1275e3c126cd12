// Map snapshots, ~map and ~save_map of EskfNodelet (map_publisher.hpp says
// which thread calls what).
#include "hapi_eskf/ros/map_publisher.hpp"

#include "hapi_eskf/map_file/map_writer.hpp"
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

void MapPublisher::takeSnapshot(const std::function<std::vector<MapPoint>()>& read_map,
                                const std::function<FileMap()>& read_file_map, const ros::Time& stamp) {
  last_snapshot_wall_ = ros::WallTime::now();
  const bool for_save = save_requested_.exchange(false);
  auto pts = std::make_shared<const std::vector<MapPoint>>(read_map());
  std::shared_ptr<const FileMap> file_map;
  if (for_save) file_map = std::make_shared<const FileMap>(read_file_map());
  {
    std::lock_guard<std::mutex> lk(mu_);
    snapshot_ = std::move(pts);
    snapshot_stamp_ = stamp;
    ++generation_;
    if (file_map) {
      file_map_ = std::move(file_map);
      ++file_generation_;
    }
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

bool MapPublisher::waitForSnapshot(std::uint64_t after, Snapshot* out, std::shared_ptr<const FileMap>* file_map) {
  save_requested_ = true;
  requested_ = true;
  std::unique_lock<std::mutex> lk(mu_);
  cv_.wait_for(lk, std::chrono::seconds(2), [&] { return file_generation_ > after || closed_; });
  *out = snapshot_;
  *file_map = file_map_;
  return file_generation_ > after;
}

bool MapPublisher::save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::uint64_t gen;
  {
    std::lock_guard<std::mutex> lk(mu_);
    gen = file_generation_;
  }
  Snapshot snap;
  std::shared_ptr<const FileMap> file_map;
  if (!waitForSnapshot(gen, &snap, &file_map)) {
    res.success = false;
    res.message = "no fresh map snapshot from the worker within 2 s";
    return true;
  }
  // One name for both files: <stem>.hmap (the map to load) and <stem>.ply.
  const std::string map_path = timestampedPath(output_dir_, "hapi_map", "hmap");
  const std::string ply_path = map_path.substr(0, map_path.size() - 4) + "ply";
  std::string err = writePly(ply_path, snap ? *snap : std::vector<MapPoint>{});
  if (err.empty()) {
    err = file_map->error;
    if (err.empty()) {
      const map_file::MapError e = map_file::writeMapFile(map_path, file_map->map);
      if (e) err = e.message;
    }
    if (!err.empty()) err = "map file not written (" + err + "); the points are in " + ply_path;
  }
  res.success = err.empty();
  res.message = res.success ? map_path : err;
  if (res.success)
    ROS_INFO_NAMED(log_name_, "saved %zu landmarks and %zu keyframes to %s and %s", file_map->map.landmarks.size(),
                   file_map->map.keyframes.size(), map_path.c_str(), ply_path.c_str());
  else
    ROS_ERROR_NAMED(log_name_, "~save_map failed: %s", err.c_str());
  return true;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
