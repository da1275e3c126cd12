// The session map of hapi_eskf/EskfNodelet (docs/DESIGN.md "Map file"): the
// stereo calibration heard on ~left/camera_info and ~right/camera_info (what
// a saved map records and a loaded one is checked against), the map loaded
// from ~map_file or ~load_map, and the relocalisation state /diagnostics
// reports. The map logic itself is ROS-free (session/map_session.hpp).
//
// A loaded map stays the session's map: every filter start (the first frame,
// ~reset, a time jump, a restart after a backend fault) loads it into the
// fresh filter, which then holds its output until a frame relocalises in it.
// A map that fails a check is never the session's map (nothing loads half).
//
// Threads: the camera_info callbacks, the ~load_map service, the worker
// (load at a filter start, frame reports, the header of a map to save) and
// the diagnostics timer; mu_ guards everything.
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/map_file/map_error.hpp"
#include "hapi_eskf/ros/map_calibration.hpp"
#include "hapi_eskf/ros/params.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <sensor_msgs/CameraInfo.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace hapi_eskf {
namespace ros_glue {


class MapSession {
 public:
  // `log_name` is the nodelet's logger name.
  MapSession(const NodeletParams& params, std::string log_name);

  // --- camera_info callbacks ---
  void leftInfo(const sensor_msgs::CameraInfo::ConstPtr& msg);
  void rightInfo(const sensor_msgs::CameraInfo::ConstPtr& msg);
  // The running stereo calibration; false and *why before both messages
  // came or when they are not a rectified pair.
  bool calibration(map_file::MapCalibration* out, std::string* why) const;

  // --- start-up (~map_file) and ~load_map ---
  // Reads and checks `path` (the layout, every value, the descriptor type
  // when `descriptor_type` >= 0, the calibration when known, and whether
  // the settings can load it). On success it is the session's map; on a
  // fault a ROS error names it, map_load_failures counts it and the
  // session's map is unchanged.
  map_file::MapError read(const std::string& path, int descriptor_type, std::size_t* landmarks);

  // --- worker ---
  // After the filter's reset at a filter start: the session's map into it.
  // True when a map was loaded (the filter waits to relocalise in it); a
  // fault (descriptor length, calibration, the filter's refusal) is
  // reported, counted, and the session goes on without a map.
  bool loadInto(SlamBackend* backend, int descriptor_length);
  // A processed frame's report: relocalised in the loaded map?
  void onFrame(const IterationReport& report, double stamp);
  // Whether the filter still waits to relocalise in a loaded map.
  bool waiting() const;
  // The map file's header of a save: everything but the landmarks. False
  // and *why without a calibration.
  bool header(const std::string& camera_frame, uint8_t descriptor_type, uint32_t descriptor_length,
              const std::optional<CameraExtrinsic>& imu_cam, map_file::MapData* out, std::string* why) const;

  // --- diagnostics timer: keys map_file, relocalisation, map_loads,
  // map_load_failures, last_map_load_failure; the summary says when the
  // filter waits for the map (OK) or a map failed and none is loaded (WARN) ---
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const;

 private:
  enum class State { kNoMap, kWaiting, kRelocalised };
  void fail(const std::string& what);  // under mu_

  const NodeletParams& params_;
  const std::string log_name_;
  mutable std::mutex mu_;
  sensor_msgs::CameraInfo::ConstPtr left_, right_;
  std::shared_ptr<const map_file::MapData> map_;  // the session's map; null: none
  std::string map_path_;
  State state_ = State::kNoMap;
  double relocalised_at_ = 0.0;
  const char* relocalised_on_ = "";  // "its landmarks" or "a keyframe" (IterationReport::keyframe_fit)
  std::string last_failure_;
  std::uint64_t loads_ = 0, load_failures_ = 0;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
