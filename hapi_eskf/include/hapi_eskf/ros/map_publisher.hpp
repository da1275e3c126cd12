// Map output of hapi_eskf/EskfNodelet: snapshots of the landmark pool taken by
// the worker (at ~map_publish_rate, or at once when ~save_map asks for one),
// published by a wall timer as ~map (sensor_msgs/PointCloud2, latched) and
// written by ~save_map as a map file (map_file/map_writer.hpp, what
// ~map_file and ~load_map read) and a PLY beside it with the same name.
// Snapshots are immutable and shared, so neither the timer nor the service
// ever touches the filter.
//
// Threads: the worker takes snapshots; the map timer publishes; the
// ~save_map service waits for a fresh snapshot. mu_ guards the snapshot and
// its generation; last_snapshot_wall_ is the worker's own.
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/ros/conversions.hpp"
#include "hapi_eskf/ros/params.hpp"

#include <ros/publisher.h>
#include <ros/time.h>
#include <std_srvs/Trigger.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

// The pool as a map file's content, made by the worker for ~save_map;
// `error` says why there is none (no calibration, not the ES-EKF, ...).
struct FileMap {
  map_file::MapData map;
  std::string error;
};

class MapPublisher {
 public:
  // `log_name` is the nodelet's logger name.
  MapPublisher(const NodeletParams& params, ros::Publisher map_pub, std::string log_name);

  // --- worker thread ---
  // True when ~save_map asked for a snapshot or 1 / ~map_publish_rate has
  // passed since the last one.
  bool snapshotDue();
  // A new snapshot: `read_map` (called here, on the worker thread) reads the
  // pool in the published world frame; `read_file_map`, called only while
  // ~save_map waits, the same as a map file's content; `stamp` is that of
  // the last frame.
  void takeSnapshot(const std::function<std::vector<MapPoint>()>& read_map,
                    const std::function<FileMap()>& read_file_map, const ros::Time& stamp);

  // --- map timer: publishes the newest snapshot if not published yet ---
  void publishLatest();

  // --- ~save_map service: from a fresh snapshot, hapi_map_<time>.hmap and
  // hapi_map_<time>.ply in ~output_dir; success when both are written, the
  // message is the map file's path (or what failed) ---
  bool save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);

  // Shutdown: wakes a ~save_map waiting for a snapshot that will not come.
  void close();

 private:
  using Snapshot = std::shared_ptr<const std::vector<MapPoint>>;
  // The first snapshot taken for a ~save_map after file generation `after`.
  bool waitForSnapshot(std::uint64_t after, Snapshot* out, std::shared_ptr<const FileMap>* file_map);

  const std::string world_frame_, output_dir_;
  const double period_;  // [s] 1 / ~map_publish_rate
  const std::string log_name_;
  ros::Publisher map_pub_;
  std::atomic<bool> requested_{false}, save_requested_{false};
  ros::WallTime last_snapshot_wall_;

  std::mutex mu_;
  std::condition_variable cv_;
  Snapshot snapshot_;
  ros::Time snapshot_stamp_;
  std::uint64_t generation_ = 0, published_generation_ = 0;
  std::shared_ptr<const FileMap> file_map_;  // of the newest snapshot taken for ~save_map
  std::uint64_t file_generation_ = 0;
  bool closed_ = false;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
