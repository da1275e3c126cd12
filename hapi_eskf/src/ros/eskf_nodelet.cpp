// hapi_eskf/EskfNodelet: wiring of the node and the worker that owns the
// filter (eskf_nodelet.hpp says what runs on which thread).
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "hapi_eskf/ros/eskf_nodelet.hpp"

#include "hapi_eskf/map_file/map_checks.hpp"
#include "hapi_eskf/session/map_session.hpp"
#include "hapi_eskf/ros/conversions.hpp"
#include "hapi_eskf/slam_backend_factory.hpp"

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/PointCloud2.h>

#include <sys/stat.h>

#include <cstdint>
#include <vector>

namespace hapi_eskf {

using ros_glue::Reject;

EskfNodelet::~EskfNodelet() {
  // Stop every entry point (timers, callbacks, services), then the worker:
  // after this, no thread calls into a member while the members go.
  map_timer_.stop();
  diag_timer_.stop();
  landmarks_in_.shutdown();
  imu_in_.shutdown();
  left_info_in_.shutdown();
  right_info_in_.shutdown();
  reset_srv_.shutdown();
  save_map_srv_.shutdown();
  load_map_srv_.shutdown();
  save_traj_srv_.shutdown();
  refine_srv_.shutdown();
  stop_ = true;
  mailbox_.close();
  if (map_) map_->close();  // a ~save_map waiting for a snapshot returns
  if (worker_.joinable()) worker_.join();
}

void EskfNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  if (!checkStartup()) return;  // inert: nothing below is started
  fault_policy_ = BackendFaultPolicy(params_.allow_cpu_fallback);

  validation_.max_measurements = static_cast<std::uint32_t>(params_.max_measurements_per_msg);
  validation_.expected_frame = params_.camera_frame;
  camera_frame_ = params_.camera_frame;
  stamp_guard_ = std::make_unique<hapi_nodelet_kit::StampGuard>(params_.time_jump_reset);

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  // Listen only when a lookup is needed (IMU mounting, base frame): otherwise
  // the node would buffer its own high-rate TF for nothing.
  if (params_.usesImu() || !params_.base_frame.empty())
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  stats_ = std::make_unique<ros_glue::NodeletStatistics>(params_.usesImu());
  self_check_ = std::make_unique<ros_glue::SelfCheck>(params_, *stats_);
  if (params_.usesImu()) imu_ = std::make_unique<ros_glue::ImuInput>(params_, *tf_buffer_, *stats_, getName());

  // Topics are relative to the nodelet's namespace/name: a nodelet named
  // `eskf` publishes /eskf/odom etc. (private handle) and reads `landmarks`
  // from there too, remapped by the launch file to the front end's output.
  output_ = std::make_unique<ros_glue::OutputPublisher>(
      params_, pnh.advertise<nav_msgs::Odometry>("odom", 10),
      pnh.advertise<geometry_msgs::PoseWithCovarianceStamped>("pose", 10), imu_.get(), *stats_, getName());
  trajectory_ = std::make_unique<ros_glue::TrajectoryRecorder>(params_, pnh.advertise<nav_msgs::Path>("path", 1, true),
                                                               getName());
  map_ = std::make_unique<ros_glue::MapPublisher>(params_, pnh.advertise<sensor_msgs::PointCloud2>("map", 1, true),
                                                  getName());
  map_session_ = std::make_unique<ros_glue::MapSession>(params_, getName());
  KeyframeRecorderSettings keyframe_settings;
  keyframe_settings.min_distance = params_.keyframe_distance;
  keyframe_settings.min_angle_deg = params_.keyframe_angle;
  keyframe_settings.max_keyframes = static_cast<std::size_t>(params_.max_keyframes);
  keyframes_ = std::make_unique<KeyframeRecorder>(keyframe_settings);
  std::size_t map_landmarks = 0;
  if (!params_.map_file.empty()) map_session_->read(params_.map_file, -1, &map_landmarks);  // a fault is reported

  reset_srv_ = pnh.advertiseService("reset", &EskfNodelet::resetService, this);
  save_map_srv_ = pnh.advertiseService("save_map", &ros_glue::MapPublisher::save, map_.get());
  load_map_srv_ = pnh.advertiseService("load_map", &EskfNodelet::loadMapService, this);
  save_traj_srv_ = pnh.advertiseService("save_trajectory", &ros_glue::TrajectoryRecorder::save, trajectory_.get());
  refiner_ = std::make_unique<ros_glue::GraphRefiner>(params_, getName());
  refine_srv_ = pnh.advertiseService("refine", &ros_glue::GraphRefiner::refine, refiner_.get());

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  updater_->setHardwareID(kHardwareId);
  updater_->add(kStatusName, [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    stats_->diagnose(stat, mailbox_.dropped(), landmarks_in_.resubscriptions() + imu_in_.resubscriptions());
    map_session_->diagnose(stat);
    stat.add("keyframes", keyframes_->size());  // for ~save_map
    stat.add("keyframes_not_kept_full", keyframes_->notKeptFull());
  });
  updater_->add(kSelfCheckName, self_check_.get(), &ros_glue::SelfCheck::produce);
  diag_timer_ = nh.createWallTimer(ros::WallDuration(params_.diagnostics_period),
                                   [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  map_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / params_.map_publish_rate),
                                  [this](const ros::WallTimerEvent&) { map_->publishLatest(); });

  worker_ = std::thread(&EskfNodelet::workerLoop, this);

  // Subscribe last: callbacks may run as soon as this returns.
  // The ROS queue only has to absorb a burst until the (fast) callback runs;
  // rate mismatch is handled by the mailbox, where drops are counted.
  const double max_wait = 2 * params_.input_timeout;
  left_info_in_ = pnh.subscribe("left/camera_info", 1, &ros_glue::MapSession::leftInfo, map_session_.get());
  right_info_in_ = pnh.subscribe("right/camera_info", 1, &ros_glue::MapSession::rightInfo, map_session_.get());
  landmarks_in_.start(
      nh,
      [this, pnh]() mutable {
        return pnh.subscribe("landmarks", 10, &EskfNodelet::landmarksCallback, this,
                             ros::TransportHints().tcpNoDelay());
      },
      params_.input_timeout, max_wait, getName());
  if (params_.usesImu())
    imu_in_.start(
        nh, [this, nh]() mutable { return nh.subscribe(params_.imu_topic, 400, &EskfNodelet::imuCallback, this); },
        params_.input_timeout, max_wait, getName());

  NODELET_INFO("EskfNodelet: algorithm %s, backend %s/%s, K_max %d, motion model %s, world_frame '%s', camera_frame '%s', "
               "base_frame '%s', imu %s",
               toString(params_.filter.backend_algorithm), toString(params_.filter.backend),
               toString(params_.filter.precision), params_.filter.max_landmarks,
               toString(params_.filter.motion_model), params_.world_frame.c_str(),
               camera_frame_.empty() ? "(from first message)" : camera_frame_.c_str(), params_.base_frame.c_str(),
               params_.usesImu() ? params_.imu_topic.c_str() : "off");
  const CalibrationLayout calib = calibrationLayout(params_.filter);
  if (params_.filter.motion_model == MotionModelKind::kInertial &&
      (params_.filter.calib_cam_extrinsics || params_.filter.calib_cam_timeoffset) && !calib.any())
    NODELET_WARN("calib_cam_extrinsics / calib_cam_timeoffset ignored: backend_algorithm %s does not estimate the "
                 "calibration (the configured extrinsic and imu_time_offset are used as they are)",
                 toString(params_.filter.backend_algorithm));
  else if (calib.any())
    NODELET_INFO("online calibration: extrinsic %s, time offset %s (docs/DESIGN.md \"Online calibration\")",
                 calib.extrinsic >= 0 ? "on" : "off", calib.time_offset >= 0 ? "on" : "off");
}

bool EskfNodelet::checkStartup() {
  hapi_nodelet_kit::ParamReader reader(getPrivateNodeHandle());
  ros_glue::readParams(reader, &params_);
  for (const std::string& w : reader.warnings()) NODELET_WARN("%s", w.c_str());
  if (!reader.ok()) {
    startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "invalid parameters", reader.errors());
    return false;
  }
  // Fail at start-up, not at the first frame, when the requested back end
  // cannot run (the descriptor length is only known from the first message).
  std::string not_built;
  if (!slamBackendBuilt(params_.filter.backend_algorithm, &not_built)) {
    startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "back end not available", {"~" + not_built});
    return false;
  }
  if (params_.filter.backend_algorithm == BackendAlgorithm::kEskf && params_.filter.backend == BackendKind::kCuda) {
    std::string why;
    // With the largest descriptors a message may carry: the pool is sized
    // before the first message says which.
    if (!cudaPoolFits(params_.filter, ros_glue::kMaxDescriptorLength, &why)) {
      if (!params_.allow_cpu_fallback) {
        startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(), "CUDA backend unavailable",
                        {"~backend=cuda cannot run: " + why +
                         "; ~allow_cpu_fallback is false (true: run on the cpu backend instead)"});
        return false;
      }
      NODELET_WARN("*** ~backend=cuda cannot run (%s): FALLING BACK TO THE CPU BACKEND "
                   "(set ~allow_cpu_fallback:=false to make this a start-up failure) ***",
                   why.c_str());
      params_.filter.backend = BackendKind::kCpu;
    }
  }
  struct stat st {};
  if (stat(params_.output_dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    NODELET_WARN("~output_dir '%s' is not an existing directory: ~save_map/~save_trajectory will fail",
                 params_.output_dir.c_str());
  return true;
}

// ---------------------------------------------------------------- callbacks

void EskfNodelet::reject(Reject r, const std::string& detail) {
  ++stats_->counters.rejected[static_cast<int>(r)];
  NODELET_ERROR_THROTTLE(1.0, "rejected StereoLandmarks (%s): %s", ros_glue::rejectName(r), detail.c_str());
}

void EskfNodelet::landmarksCallback(const hapi_msgs::StereoLandmarks::ConstPtr& msg) {
  landmarks_in_.received();
  ++stats_->counters.frames_received;
  Work w;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    const ros_glue::ValidationResult v = ros_glue::validateLandmarks(*msg, validation_);
    if (!v.ok()) {
      reject(v.reason, v.detail);
      return;
    }
    const hapi_nodelet_kit::StampCheck sc =
        stamp_guard_->check(static_cast<std::int64_t>(msg->header.stamp.toNSec()));
    if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
      reject(Reject::kStampBackwards, "stamp " + std::to_string(msg->header.stamp.toSec()) +
                                          " not newer than the last accepted " +
                                          std::to_string(sc.previousSec()));
      return;
    }
    if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset) {
      ++stats_->counters.time_jumps;
      NODELET_WARN("time jumped backwards (bag loop / clock reset) to %.3f: resetting the filter and the path",
                   msg->header.stamp.toSec());
      ++epoch_;
    }
    // The first accepted message fixes the camera frame and, once it carries
    // landmarks, the descriptor type and length of the pool.
    if (camera_frame_.empty()) {
      camera_frame_ = msg->header.frame_id;
      validation_.expected_frame = camera_frame_;
    }
    if (imu_) imu_->onLandmarks(camera_frame_, msg->header.stamp.toSec());
    if (validation_.descriptor_length == 0 && !msg->landmarks.empty()) {
      validation_.descriptor_length = msg->descriptor_length;
      validation_.descriptor_type = msg->descriptor_type;
    }
    w.frame_id = camera_frame_;
    w.stamp = msg->header.stamp;
    w.epoch = epoch_.load();
  }
  ++stats_->counters.frames_accepted;
  w.frame = ros_glue::toStereoFrame(*msg);
  mailbox_.put(std::move(w));  // an untaken older frame is dropped and counted by the mailbox
}

void EskfNodelet::imuCallback(const sensor_msgs::Imu::ConstPtr& msg) {
  imu_in_.received();
  // IMU-rate output right here (a pose-block step, no filter access), so it
  // keeps flowing while the worker is busy with a frame.
  if (const std::optional<ros_glue::TimedImuSample> s = imu_->accept(*msg)) output_->publishImuRate(*s);
}

bool EskfNodelet::resetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = requestReset();
  res.message = res.success ? "filter reset; the next frame initialises it" : "worker did not acknowledge the reset";
  return true;
}

// A good map becomes the session's map and the filter restarts, so that the
// next frame starts it in the map; a bad one leaves everything as it was.
bool EskfNodelet::loadMapService(hapi_msgs::LoadMap::Request& req, hapi_msgs::LoadMap::Response& res) {
  int descriptor_type = -1;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    if (validation_.descriptor_length > 0) descriptor_type = validation_.descriptor_type;
  }
  std::size_t landmarks = 0;
  const map_file::MapError err = map_session_->read(req.path, descriptor_type, &landmarks);
  res.success = !err && requestReset();
  res.landmarks = res.success ? static_cast<std::uint32_t>(landmarks) : 0;
  if (err)
    res.message = err.message;
  else if (!res.success)
    res.message = "map read, but the worker did not acknowledge the reset";
  else
    res.message = "map read (" + std::to_string(landmarks) +
                  " landmarks); the next frame starts the filter in it, output resumes once it relocalises";
  return true;
}

bool EskfNodelet::requestReset() {
  const std::uint64_t target = ++epoch_;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    stamp_guard_->clear();  // the next frame starts the new filter, whatever its stamp
  }
  // The worker resets within one loop period (it wakes at least every 50 ms).
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(2.0);
  while (worker_epoch_.load() < target && ros::WallTime::now() < deadline) ros::WallDuration(0.005).sleep();
  return worker_epoch_.load() >= target;
}

// ------------------------------------------------------------------- worker

void EskfNodelet::workerLoop() {
  ros_glue::NodeletStatistics::Counters& count = stats_->counters;
  while (!stop_) {
    std::optional<Work> w = mailbox_.take(std::chrono::milliseconds(50));
    if (stop_) break;
    const std::uint64_t epoch = epoch_.load();
    if (epoch > worker_epoch_.load()) {
      resetFilter();
      worker_epoch_ = epoch;
    }
    if (w) {
      if (stopped_) {
        ++count.frames_failed;  // the filter stopped after a backend fault (reported)
      } else if (w->epoch < worker_epoch_.load()) {
        ++count.frames_stale;  // accepted before a reset: belongs to the old timeline
      } else {
        try {
          if (!process(*w)) ++count.frames_failed;
        } catch (const std::exception& e) {  // never let the worker die (e.g. std::bad_alloc)
          ++count.filter_errors;
          ++count.frames_failed;
          NODELET_ERROR_THROTTLE(1.0, "exception while processing a frame: %s", e.what());
        }
      }
    }
    if (map_->snapshotDue()) takeSnapshot();
  }
}

void EskfNodelet::resetFilter() {
  const std::uint64_t resets = ++stats_->counters.resets;
  need_init_ = true;
  if (imu_) imu_->clear();
  trajectory_->clear(last_stamp_);
  output_->restart();
  tf_buffer_->clear();  // after a bag loop its data lies in the "future" of the new timeline
  if (backend_) backend_->reset(PoseState(), 0.0);  // empties the pool now: the map snapshot below is empty
  refiner_->clear();
  takeSnapshot();
  NODELET_WARN("filter reset (#%llu): path and map cleared", static_cast<unsigned long long>(resets));
}

bool EskfNodelet::ensureFilter(const Work& w) {
  if (backend_) return true;
  if (w.frame.measurements.empty()) return false;  // the descriptor length is not known yet
  std::string err;
  const bool cuda = params_.filter.backend_algorithm == BackendAlgorithm::kEskf &&
                    params_.filter.backend == BackendKind::kCuda;
  std::unique_ptr<SlamBackend> backend =
      makeSlamBackend(params_.filter, w.frame.descriptor_length, CameraExtrinsic(), &err);
  if (!backend && cuda && params_.allow_cpu_fallback) {
    NODELET_WARN("*** CUDA backend could not be created (%s): FALLING BACK TO THE CPU BACKEND ***", err.c_str());
    params_.filter.backend = BackendKind::kCpu;
    backend = makeSlamBackend(params_.filter, w.frame.descriptor_length, CameraExtrinsic(), &err);
  }
  if (!backend) {
    ++stats_->counters.filter_errors;
    stop(std::string("cannot create the ") + toString(params_.filter.backend_algorithm) + " back end (" +
         toString(params_.filter.backend) + "): " + err);
    return false;
  }
  backend_ = std::move(backend);
  refiner_->attach(backend_.get());
  stats_->recordBackend(backend_->storage(), backend_->memoryBytes());
  NODELET_INFO("filter created: algorithm %s, storage %s, %.1f MiB, descriptor length %d", backend_->name(),
               backend_->storage().c_str(), backend_->memoryBytes() / ros_glue::kBytesPerMiB, w.frame.descriptor_length);
  return true;
}

// REP-105: with ~base_frame the published map is anchored at the FIRST BASE
// pose (T_map_world = T_base_cam, the filter's world being the first camera),
// so map is level with the robot instead of having the optical frame's
// z-forward axes. The camera mounting is looked up once (assumed rigid).
bool EskfNodelet::anchorWorld(const Work& w) {
  if (params_.base_frame.empty()) {
    output_->setMapAnchor(Eigen::Isometry3d::Identity());
    return true;
  }
  try {
    const auto t = tf_buffer_->lookupTransform(params_.base_frame, w.frame_id, ros::Time(0), ros::Duration(0.2));
    output_->setMapAnchor(ros_glue::toIsometry(t.transform));
    return true;
  } catch (const tf2::TransformException& e) {
    ++stats_->counters.filter_errors;
    NODELET_ERROR_THROTTLE(2.0, "~base_frame set but no TF %s <- %s: %s (frame skipped)", params_.base_frame.c_str(),
                           w.frame_id.c_str(), e.what());
    return false;
  }
}

void EskfNodelet::applyImu(double up_to) {
  // The extrinsic arrives with the first accepted sample (TF); it is static.
  if (!extrinsic_applied_) {
    const std::optional<CameraExtrinsic> e = imu_->extrinsic();
    if (!e) return;  // no sample accepted yet: nothing to apply either
    const Status st = backend_->setCameraExtrinsic(*e);
    if (st != Status::kOk) {
      ++stats_->counters.filter_errors;
      NODELET_ERROR_THROTTLE(2.0, "camera-IMU extrinsic from TF rejected: %s (IMU not used)", toString(st));
      return;
    }
    extrinsic_applied_ = true;
  }
  for (const ros_glue::TimedImuSample& s : imu_->takeUpTo(up_to)) {
    if (s.sample.stamp <= backend_->time()) continue;  // older than the filter: nothing to predict
    const Status st = backend_->addImu(s.sample);
    if (st == Status::kOk) {
      ++stats_->counters.imu_used;
    } else {
      ++stats_->counters.imu_rejected_by_filter;
      ++stats_->counters.imu_dropped;
      NODELET_WARN_THROTTLE(2.0, "the filter rejected the IMU sample at %.3f: %s", s.sample.stamp, toString(st));
    }
  }
}

bool EskfNodelet::process(Work& w) {
  ros_glue::NodeletStatistics::Counters& count = stats_->counters;
  if (!ensureFilter(w)) return false;
  const double stamp = w.frame.stamp;
  Status st = Status::kOk;
  IterationReport rep;
  if (need_init_) {
    if (!anchorWorld(w)) return false;
    st = backend_->reset(PoseState(), stamp);
    if (st == Status::kBackendError) return onBackendFault(stamp);
    if (st != Status::kOk) {
      ++count.filter_errors;
      NODELET_ERROR_THROTTLE(1.0, "filter reset failed: %s", toString(st));
      return false;
    }
    need_init_ = false;
    keyframes_->clear();  // a new timeline: the old keyframes are in another world frame
    // A loaded map is the filter's world: published as it is, unanchored.
    if (map_session_->loadInto(backend_.get(), w.frame.descriptor_length)) output_->unanchorMap();
    if (imu_) imu_->dropUpTo(stamp);  // samples before the first frame are not needed
  } else if (imu_) {
    applyImu(stamp);
  }
  const ros::WallTime t0 = ros::WallTime::now();
  if (params_.test_frame_delay > 0.0) ros::WallDuration(params_.test_frame_delay).sleep();  // rostests only
  if (w.frame.measurements.empty()) {
    st = backend_->predictTo(stamp);  // nothing seen: keep the motion model running
    rep.t_total_ms = rep.t_predict_ms = (ros::WallTime::now() - t0).toSec() * 1e3;
    rep.n_landmarks = backend_->numLandmarks();
  } else {
    st = refiner_->processFrame(*backend_, w.frame, &rep);  // recorded for ~refine when the ES-EKF runs
  }
  if (st == Status::kBackendError) return onBackendFault(stamp);
  fault_policy_.onSuccess();
  if (st == Status::kAwaitingImu) {
    // Inertial model: the first alignment_window of IMU samples sets gravity.
    ++count.frames_awaiting_imu;
    NODELET_INFO_THROTTLE(1.0, "aligning to gravity: frame at %.3f waits for IMU samples (not processed)", stamp);
    return true;
  }
  if (st != Status::kOk) {
    ++count.filter_errors;
    stats_->recordFilterError(toString(st));
    NODELET_ERROR_THROTTLE(1.0, "filter rejected the frame at %.3f: %s (state unchanged)", stamp, toString(st));
    return false;
  }
  ++count.frames_processed;
  if (!rep.relocalising) recordKeyframe(w.frame);
  const bool in_loaded_map = map_session_->waiting();
  map_session_->onFrame(rep, stamp);
  if (rep.relocalised) {
    ++count.relocalisations;
    if (!in_loaded_map)
      NODELET_WARN("relocalised against the map at %.3f after an input gap (EskfSettings relocalise_gap)", stamp);
  }
  if (rep.relocalising) {
    // Lost after an input gap, or not yet placed in a loaded map: the pose
    // is not known in the map, so nothing is published until a frame the
    // map supports has relocalised the filter.
    ++count.frames_relocalising;
    if (in_loaded_map)
      NODELET_INFO_THROTTLE(2.0, "waiting to relocalise in the loaded map (no output)");
    else
      NODELET_WARN_THROTTLE(1.0, "lost after an input gap: waiting for a frame the map supports (no output)");
    return true;
  }
  if (rep.vision_led) ++count.frames_vision_led;
  if (rep.zero_velocity.still.still) ++count.frames_still;
  if (rep.zero_velocity.fused) ++count.zero_velocity_fused;
  if (rep.zero_velocity.tested && !rep.zero_velocity.fused) ++count.zero_velocity_rejected;
  if (rep.scene_moving) {
    ++count.frames_scene_moving;
    NODELET_WARN_THROTTLE(2.0, "the scanned surface moves while the device is still: tracking relative to the surface");
  }
  if (rep.update_skipped) {
    ++count.update_skips;
    NODELET_WARN_THROTTLE(1.0, "update skipped at %.3f (innovation covariance not PD): prediction only", stamp);
  }
  stats_->recordFrame(rep, backend_->numLandmarks(), backend_->memoryBytes());
  self_check_->frameMeasured(static_cast<int>(w.frame.measurements.size()));
  PoseBlockState pose_block;
  if (backend_->poseBlockState(&pose_block)) {
    stats_->recordCalibration(calibrationEstimate(calibrationLayout(params_.filter), pose_block));
    stats_->recordImuNoise(pose_block.x.imu_noise);
  }
  last_stamp_ = w.stamp;
  const ros_glue::CameraInMap T_map_cam =
      output_->publishFrame(w.stamp, w.frame_id, *backend_, rep.scene_moving);
  // The correction is in the outputs now (with an IMU model: in the samples
  // publishFrame caught up, or the next one).
  stats_->recordLatency((ros::Time::now() - w.stamp).toSec());
  trajectory_->record(w.stamp, T_map_cam);
  return true;
}

bool EskfNodelet::onBackendFault(double stamp) {
  ros_glue::NodeletStatistics::Counters& count = stats_->counters;
  ++count.filter_errors;
  ++count.backend_faults;
  const std::string what = backend_->storage() + ": " + backend_->lastError();
  stats_->recordFilterError("backend fault: " + what);
  const FaultAction action = fault_policy_.onFault(params_.filter.backend);
  NODELET_ERROR("backend fault in the frame at %.3f (%s): frame dropped, filter and map discarded; %s", stamp,
                what.c_str(), toString(action));
  backend_.reset();  // never continued on a backend whose state is not trusted
  resetFilter();  // path, map and IMU buffer cleared; the next frame starts a new filter
  if (action == FaultAction::kFallBackToCpu) {
    NODELET_WARN("*** repeated CUDA backend faults: FALLING BACK TO THE CPU BACKEND ***");
    params_.filter.backend = BackendKind::kCpu;
  } else if (action == FaultAction::kStop) {
    stop("repeated backend faults, last: " + what);
  }
  return false;
}

void EskfNodelet::stop(const std::string& why) {
  stopped_ = true;
  stats_->recordStop(why);
  NODELET_ERROR("filter STOPPED: %s (no more output; restart the node)", why.c_str());
}

// The map in the published world frame, empty while the filter waits for its
// first frame (after a reset).
void EskfNodelet::takeSnapshot() {
  map_->takeSnapshot(
      [this] {
        if (!backend_ || need_init_) return std::vector<ros_glue::MapPoint>{};
        return ros_glue::toMapPoints(backend_->landmarks(), output_->mapFromWorld());
      },
      [this] { return fileMap(); }, last_stamp_);
}

// The frame is kept for ~save_map when the camera has moved far enough from
// the last keyframe (keyframe_recorder.hpp).
void EskfNodelet::recordKeyframe(const StereoFrame& frame) {
  const Eigen::Isometry3d T_world_cam =
      ros_glue::toCameraInMap(backend_->pose(), Eigen::Isometry3d::Identity()).isometry();
  keyframes_->offer(frame, T_world_cam, [this] { return backend_->cameraPoseCovariance(); });
}

ros_glue::FileMap EskfNodelet::fileMap() {
  ros_glue::FileMap out;
  if (!backend_ || need_init_) {
    out.error = "the filter has not started";
    return out;
  }
  std::uint8_t descriptor_type = 0;
  std::uint32_t descriptor_length = 0;
  std::string camera_frame;
  {
    std::lock_guard<std::mutex> lk(input_mu_);
    camera_frame = camera_frame_;
    descriptor_type = validation_.descriptor_type;
    descriptor_length = validation_.descriptor_length;
  }
  map_file::MapData header;
  if (!map_session_->header(camera_frame, descriptor_type, descriptor_length,
                            imu_ ? imu_->extrinsic() : std::nullopt, &header, &out.error))
    return out;
  int skipped = 0;
  if (const map_file::MapError e =
          map_file::mapFromBackend(*backend_, output_->mapFromWorld(), header, &out.map, &skipped))
    out.error = e.message;
  else if (skipped > 0)
    NODELET_WARN("~save_map: %d landmarks left out (covariance no longer positive definite)", skipped);
  // Keyframes that fail the file's checks (a pose covariance that lost its
  // definiteness) are left out, as such landmarks are.
  int skipped_keyframes = 0;
  for (Keyframe& k : keyframes_->keyframes(output_->mapFromWorld())) {
    if (map_file::checkKeyframe(k, descriptor_length, out.map.keyframes.size()))
      ++skipped_keyframes;
    else
      out.map.keyframes.push_back(std::move(k));
  }
  if (skipped_keyframes > 0)
    NODELET_WARN("~save_map: %d keyframes left out (failed the map file's checks)", skipped_keyframes);
  return out;
}

}  // namespace hapi_eskf

PLUGINLIB_EXPORT_CLASS(hapi_eskf::EskfNodelet, nodelet::Nodelet)
