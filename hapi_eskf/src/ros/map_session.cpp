// The session map of EskfNodelet (map_session.hpp).
#include "hapi_eskf/ros/map_session.hpp"

#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/map_file/map_reader.hpp"
#include "hapi_eskf/session/map_session.hpp"

#include <ros/console.h>
#include <ros/time.h>

#include <cmath>
#include <utility>

namespace hapi_eskf {
namespace ros_glue {

MapSession::MapSession(const NodeletParams& params, std::string log_name)
    : params_(params), log_name_(std::move(log_name)) {}

void MapSession::leftInfo(const sensor_msgs::CameraInfo::ConstPtr& msg) {
  std::lock_guard<std::mutex> lk(mu_);
  left_ = msg;
}

void MapSession::rightInfo(const sensor_msgs::CameraInfo::ConstPtr& msg) {
  std::lock_guard<std::mutex> lk(mu_);
  right_ = msg;
}

bool MapSession::calibration(map_file::MapCalibration* out, std::string* why) const {
  sensor_msgs::CameraInfo::ConstPtr left, right;
  {
    std::lock_guard<std::mutex> lk(mu_);
    left = left_;
    right = right_;
  }
  if (!left || !right) {
    *why = "no CameraInfo on ~left/camera_info and ~right/camera_info yet (the map file records the stereo "
           "calibration)";
    return false;
  }
  if (!toMapCalibration(*left, *right, out, why)) return false;
  // The mounting is compared only where it is configured (~T_cam_imu), not
  // when it comes from TF later.
  CameraExtrinsic imu_cam;
  std::string unused;
  if (!params_.T_cam_imu.empty() && cameraInImuFromKalibr(params_.T_cam_imu, &imu_cam, &unused)) {
    out->has_imu = true;
    out->imu_cam = imu_cam;
  }
  return true;
}

void MapSession::fail(const std::string& what) {
  ++load_failures_;
  last_failure_ = what;
  ROS_ERROR_NAMED(log_name_, "map not loaded: %s (running without a map)", what.c_str());
}

map_file::MapError MapSession::read(const std::string& path, int descriptor_type, std::size_t* landmarks) {
  map_file::MapCalibration running;
  std::string why;
  const bool have_calibration = calibration(&running, &why);
  map_file::MapExpectation expect;
  expect.descriptor_type = descriptor_type;
  expect.calibration = have_calibration ? &running : nullptr;
  auto map = std::make_shared<map_file::MapData>();
  map_file::MapError err = map_file::readMapFile(path, expect, map.get());
  if (!err) err = map_file::checkLoadable(*map, params_.filter);
  std::lock_guard<std::mutex> lk(mu_);
  if (err) {
    fail("'" + path + "': " + err.message);
    return err;
  }
  *landmarks = map->landmarks.size();
  map_ = std::move(map);
  map_path_ = path;
  state_ = State::kWaiting;  // from now until a frame relocalises in it
  ROS_INFO_NAMED(log_name_, "map '%s' read: %zu landmarks and %zu keyframes in frame '%s'%s", path.c_str(),
                 *landmarks, map_->keyframes.size(), map_->map_frame.c_str(),
                 have_calibration ? "" : "; calibration compared at the first frame with camera_info");
  return {};
}

bool MapSession::loadInto(SlamBackend* backend, int descriptor_length) {
  std::shared_ptr<const map_file::MapData> map;
  {
    std::lock_guard<std::mutex> lk(mu_);
    map = map_;
    if (!map) {
      state_ = State::kNoMap;
      return false;
    }
  }
  map_file::MapError err;
  map_file::MapCalibration running;
  std::string why;
  if (static_cast<int>(map->descriptor_length) != descriptor_length)
    err = map_file::mapError(map_file::MapFault::kDescriptorType,
                             "map descriptors of " + std::to_string(map->descriptor_length) +
                                 " bytes, the front end's of " + std::to_string(descriptor_length));
  else if (calibration(&running, &why))
    err = map_file::checkSameCamera(map->calibration, running);
  if (!err) err = map_file::loadIntoBackend(*map, backend);
  std::lock_guard<std::mutex> lk(mu_);
  if (err) {
    fail("'" + map_path_ + "': " + err.message);
    map_.reset();  // never retried at the next filter start
    state_ = State::kNoMap;
    return false;
  }
  if (!why.empty())
    ROS_WARN_NAMED(log_name_, "map '%s' loaded without a calibration check: %s", map_path_.c_str(), why.c_str());
  ++loads_;
  state_ = State::kWaiting;
  ROS_INFO_NAMED(log_name_, "map '%s' loaded (%zu landmarks): waiting for a frame to relocalise in it",
                 map_path_.c_str(), map->landmarks.size());
  return true;
}

void MapSession::onFrame(const IterationReport& report, double stamp) {
  std::lock_guard<std::mutex> lk(mu_);
  if (state_ != State::kWaiting || !report.relocalised) return;
  state_ = State::kRelocalised;
  relocalised_at_ = stamp;
  relocalised_on_ = report.keyframe_fit ? "a keyframe" : "its landmarks";
  ROS_INFO_NAMED(log_name_, "relocalised in the loaded map '%s' at %.3f on %s", map_path_.c_str(), stamp,
                 relocalised_on_);
}

bool MapSession::waiting() const {
  std::lock_guard<std::mutex> lk(mu_);
  return state_ == State::kWaiting;
}

bool MapSession::header(const std::string& camera_frame, uint8_t descriptor_type, uint32_t descriptor_length,
                        const std::optional<CameraExtrinsic>& imu_cam, map_file::MapData* out,
                        std::string* why) const {
  map_file::MapData h;
  if (!calibration(&h.calibration, why)) return false;
  if (imu_cam) {
    h.calibration.has_imu = true;
    h.calibration.imu_cam = *imu_cam;
  }
  h.map_frame = params_.world_frame;
  h.camera_frame = camera_frame;
  h.created = ros::WallTime::now().toSec();
  h.descriptor_type = descriptor_type;
  h.descriptor_length = descriptor_length;
  *out = std::move(h);
  return true;
}

void MapSession::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  std::lock_guard<std::mutex> lk(mu_);
  if (state_ == State::kWaiting)
    stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::OK, "waiting to relocalise in the loaded map");
  else if (!map_ && !last_failure_.empty())
    stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::WARN, "map not loaded: %s", last_failure_.c_str());
  stat.add("map_file", map_ ? map_path_ : std::string("none"));
  stat.add("map_keyframes", map_ ? map_->keyframes.size() : std::size_t{0});
  switch (state_) {
    case State::kNoMap: stat.add("relocalisation", "no map loaded"); break;
    case State::kWaiting: stat.add("relocalisation", "waiting for the loaded map"); break;
    case State::kRelocalised: stat.addf("relocalisation", "relocalised in the loaded map at %.3f on %s", relocalised_at_, relocalised_on_);
      break;
  }
  stat.add("map_loads", loads_);
  stat.add("map_load_failures", load_failures_);
  stat.add("last_map_load_failure", last_failure_);
}

}  // namespace ros_glue
}  // namespace hapi_eskf
